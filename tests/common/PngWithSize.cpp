// SPDX-License-Identifier: BSD-3-Clause
#include "PngWithSize.h"

#include <cstddef>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <vector>

namespace emslam::test
{
namespace
{
/** CRC-32 of PNG chunks (ISO 3309, reflected polynomial 0xEDB88320). */
std::uint32_t crc32(const unsigned char* p, std::size_t n)
{
    std::uint32_t c = 0xFFFFFFFFU;
    for (std::size_t k = 0; k < n; k++)
    {
        c ^= p[k];
        for (int bit = 0; bit < 8; bit++)
        {
            c = (c & 1U) != 0 ? (c >> 1U) ^ 0xEDB88320U : c >> 1U;
        }
    }
    return c ^ 0xFFFFFFFFU;
}

void putBigEndian(unsigned char* p, std::uint32_t v)
{
    for (int k = 3; k >= 0; k--)
    {
        p[k] = static_cast<unsigned char>(v & 0xFFU);
        v >>= 8U;
    }
}
}  // namespace

void writePngDeclaring(const std::string& path, std::uint32_t width, std::uint32_t height)
{
    std::vector<unsigned char> png;
    cv::imencode(".png", cv::Mat(4, 4, CV_8UC1, cv::Scalar(7)), png);
    // Signature (8 bytes), then IHDR: length (4), "IHDR" (4), 13 data bytes, CRC (4).
    if (png.size() < 33)
    {
        throw std::runtime_error("writePngDeclaring: OpenCV wrote no IHDR chunk");
    }
    putBigEndian(&png[16], width);
    putBigEndian(&png[20], height);
    putBigEndian(&png[29], crc32(&png[12], 17));
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
}

}  // namespace emslam::test
