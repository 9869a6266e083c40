// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/ImageFile.h>
#include <emslam/io/ImageHeader.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <system_error>

namespace emslam::io
{
namespace
{
std::string sizeText(const cv::Size& s)
{
    return std::to_string(s.width) + "x" + std::to_string(s.height);
}

/** Decodes `file`, whose header declared `size`. */
cv::Mat decode(const std::string& file, const cv::Size& size)
{
    cv::Mat im = cv::imread(file, cv::IMREAD_UNCHANGED);
    if (im.empty())
    {
        throw std::runtime_error("Cannot read image '" + file + "' (not a valid image file)");
    }
    if (im.size() != size)
    {
        throw std::runtime_error(
            "Image '" + file + "' decodes to " + sizeText(im.size()) + " but its header says " +
            sizeText(size));
    }
    return im;
}
}  // namespace

cv::Size imageFileSize(const std::string& file)
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
    {
        throw std::runtime_error("Image file '" + file + "' does not exist");
    }
    const ImageHeader h = readImageHeader(file);
    if (h.width > MAX_IMAGE_SIDE || h.height > MAX_IMAGE_SIDE ||
        std::uint64_t{h.width} * h.height > MAX_IMAGE_PIXELS)
    {
        throw std::runtime_error(
            "Image '" + file + "' is " + std::to_string(h.width) + "x" + std::to_string(h.height) +
            " (" + h.format + " header): over the limit of " + std::to_string(MAX_IMAGE_PIXELS) +
            " pixels (8192x8192) and " + std::to_string(MAX_IMAGE_SIDE) + " per side; not decoded");
    }
    // Both sides fit in an int: they are at most MAX_IMAGE_SIDE.
    return {static_cast<int>(h.width), static_cast<int>(h.height)};
}

cv::Mat loadImageFile(const std::string& file)
{
    return decode(file, imageFileSize(file));
}

cv::Mat loadImageFile(
    const std::string& file, const cv::Size& expected, const std::string& expected_source)
{
    const cv::Size size = imageFileSize(file);
    if (size != expected)
    {
        throw std::runtime_error(
            "Image size mismatch: '" + file + "' is " + sizeText(size) + ", expected " +
            sizeText(expected) + " (" + expected_source + ")");
    }
    return decode(file, size);
}

}  // namespace emslam::io
