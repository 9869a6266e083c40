// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/PackedFrame.h>

#include <stdexcept>

namespace emslam::hwdrivers
{
PackedLayout packedLayoutFromString(const std::string& s)
{
    if (s == "rgb24")
    {
        return PackedLayout::PIXEL_INTERLEAVED_24;
    }
    if (s == "interleaved16")
    {
        return PackedLayout::BYTE_INTERLEAVED_16;
    }
    if (s == "planar8")
    {
        return PackedLayout::PLANAR_8;
    }
    throw std::invalid_argument(
        "unknown packed pixel layout '" + s + "' (expected rgb24, interleaved16 or planar8)");
}

std::string toString(PackedLayout layout)
{
    switch (layout)
    {
        case PackedLayout::PIXEL_INTERLEAVED_24:
            return "rgb24";
        case PackedLayout::BYTE_INTERLEAVED_16:
            return "interleaved16";
        case PackedLayout::PLANAR_8:
            return "planar8";
    }
    return "?";
}

unsigned int PackedFrameFormat::channels() const
{
    switch (layout)
    {
        case PackedLayout::PIXEL_INTERLEAVED_24:
            return 3;
        case PackedLayout::BYTE_INTERLEAVED_16:
            return 2;
        case PackedLayout::PLANAR_8:
            return planar_channels;
    }
    return 0;
}

std::size_t PackedFrameFormat::bytesPerFrame() const
{
    return static_cast<std::size_t>(channels()) * width * height;
}

namespace
{
void checkFormat(const PackedFrameFormat& fmt)
{
    if (fmt.width == 0 || fmt.height == 0)
    {
        throw std::invalid_argument("packed frame format has a zero image size");
    }
    if (fmt.layout == PackedLayout::PLANAR_8 && fmt.planar_channels != 2 &&
        fmt.planar_channels != 3)
    {
        throw std::invalid_argument(
            "planar8 frames hold 2 or 3 images, not " + std::to_string(fmt.planar_channels));
    }
}
}  // namespace

std::vector<cv::Mat> deinterleave(
    const std::uint8_t* data, std::size_t size, const PackedFrameFormat& fmt)
{
    checkFormat(fmt);
    if (data == nullptr || size != fmt.bytesPerFrame())
    {
        throw std::invalid_argument(
            "packed frame of " + std::to_string(size) + " bytes, but a " + toString(fmt.layout) +
            " frame of " + std::to_string(fmt.width) + "x" + std::to_string(fmt.height) +
            " images has " + std::to_string(fmt.bytesPerFrame()) + " bytes");
    }
    const int w = static_cast<int>(fmt.width);
    const int h = static_cast<int>(fmt.height);
    const int n = static_cast<int>(fmt.channels());
    std::vector<cv::Mat> out;
    auto* ptr = const_cast<std::uint8_t*>(data);  // the header below is only read
    if (fmt.layout == PackedLayout::PLANAR_8)
    {
        for (int k = 0; k < n; ++k)
        {
            out.push_back(
                cv::Mat(h, w, CV_8UC1, ptr + static_cast<std::size_t>(k) * fmt.width * fmt.height)
                    .clone());
        }
        return out;
    }
    const cv::Mat packed(h, w, CV_8UC(n), ptr);
    cv::split(packed, out);  // allocates owning images
    return out;
}

std::vector<std::uint8_t> interleave(
    const std::vector<cv::Mat>& images, const PackedFrameFormat& fmt)
{
    checkFormat(fmt);
    const int w = static_cast<int>(fmt.width);
    const int h = static_cast<int>(fmt.height);
    const unsigned int n = fmt.channels();
    if (images.size() != n)
    {
        throw std::invalid_argument(
            "a " + toString(fmt.layout) + " frame packs " + std::to_string(n) + " images, got " +
            std::to_string(images.size()));
    }
    for (const auto& im : images)
    {
        if (im.type() != CV_8UC1 || im.cols != w || im.rows != h)
        {
            throw std::invalid_argument(
                "interleave(): every image must be CV_8UC1 of " + std::to_string(w) + "x" +
                std::to_string(h));
        }
    }
    std::vector<std::uint8_t> out(fmt.bytesPerFrame());
    if (fmt.layout == PackedLayout::PLANAR_8)
    {
        for (unsigned int k = 0; k < n; ++k)
        {
            cv::Mat dst(h, w, CV_8UC1, out.data() + static_cast<std::size_t>(k) * w * h);
            images[k].copyTo(dst);
        }
        return out;
    }
    cv::Mat dst(h, w, CV_8UC(static_cast<int>(n)), out.data());
    cv::merge(images, dst);
    return out;
}

}  // namespace emslam::hwdrivers
