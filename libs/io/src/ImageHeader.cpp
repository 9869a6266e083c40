// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/ImageHeader.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string_view>

namespace emslam::io
{
namespace
{
[[noreturn]] void refuse(const std::string& file, const std::string& reason)
{
    throw std::runtime_error("Cannot read image '" + file + "': " + reason);
}

/** Reads `n` bytes into `out`; false if the file ends first. */
bool readBytes(std::istream& in, unsigned char* out, std::size_t n)
{
    in.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n));
    return static_cast<std::size_t>(in.gcount()) == n;
}

std::uint32_t bigEndian(const unsigned char* p, int bytes)
{
    std::uint32_t v = 0;
    for (int k = 0; k < bytes; k++)
    {
        v = (v << 8U) | p[k];
    }
    return v;
}

std::uint32_t littleEndian(const unsigned char* p, int bytes)
{
    std::uint32_t v = 0;
    for (int k = bytes - 1; k >= 0; k--)
    {
        v = (v << 8U) | p[k];
    }
    return v;
}

/** PNG: the IHDR chunk comes first, right after the 8-byte signature. */
ImageHeader readPng(std::istream& in, const std::string& file)
{
    std::array<unsigned char, 16> b{};
    if (!readBytes(in, b.data(), b.size()) || bigEndian(&b[0], 4) != 13 ||
        std::string_view(reinterpret_cast<const char*>(&b[4]), 4) != "IHDR")
    {
        refuse(file, "PNG without an IHDR header chunk");
    }
    const std::uint32_t w = bigEndian(&b[8], 4), h = bigEndian(&b[12], 4);
    // The PNG format limits sides to 2^31 - 1.
    if (w == 0 || h == 0 || w > 0x7FFFFFFFU || h > 0x7FFFFFFFU)
    {
        refuse(file, "PNG header declares an invalid size");
    }
    return {w, h, "PNG"};
}

/** JPEG: segments (marker, 2-byte length) up to a start-of-frame marker. */
ImageHeader readJpeg(std::istream& in, const std::string& file)
{
    while (true)
    {
        unsigned char c = 0;
        if (!readBytes(in, &c, 1) || c != 0xFF)
        {
            refuse(file, "JPEG with a truncated or garbled segment before its frame header");
        }
        while (c == 0xFF)  // fill bytes
        {
            if (!readBytes(in, &c, 1))
            {
                refuse(file, "truncated JPEG");
            }
        }
        const unsigned marker = c;
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8))
        {
            continue;  // markers without a segment
        }
        if (marker == 0xD9 || marker == 0xDA)
        {
            refuse(file, "JPEG without a frame header before its image data");
        }
        std::array<unsigned char, 7> b{};
        if (!readBytes(in, b.data(), 2) || bigEndian(&b[0], 2) < 2)
        {
            refuse(file, "JPEG with a truncated or garbled segment before its frame header");
        }
        const std::uint32_t length = bigEndian(&b[0], 2);
        // SOF0..SOF15, except DHT (C4), JPG (C8) and DAC (CC).
        const bool sof =
            marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
        if (sof)
        {
            if (length < 7 || !readBytes(in, &b[2], 5))
            {
                refuse(file, "truncated JPEG frame header");
            }
            const std::uint32_t h = bigEndian(&b[3], 2), w = bigEndian(&b[5], 2);
            if (w == 0 || h == 0)  // h = 0: given later by a DNL marker, which OpenCV refuses
            {
                refuse(file, "JPEG frame header declares a zero size");
            }
            return {w, h, "JPEG"};
        }
        in.seekg(static_cast<std::streamoff>(length - 2), std::ios::cur);
    }
}

/** PNM: "P<n>", then width and height as decimal text, with '#' comments. */
ImageHeader readPnm(std::istream& in, const std::string& file)
{
    // Real headers are a few dozen bytes; this bounds one full of comments.
    constexpr std::size_t MAX_HEADER_BYTES = 1U << 16;
    std::size_t read = 2;
    std::array<std::uint32_t, 2> sides{};
    for (auto& side : sides)
    {
        char c = 0;
        // Blanks and comments, then the digits.
        while (true)
        {
            if (++read > MAX_HEADER_BYTES || !in.get(c))
            {
                refuse(file, "truncated or garbled PNM header");
            }
            if (c == '#')
            {
                while (c != '\n' && c != '\r')
                {
                    if (++read > MAX_HEADER_BYTES || !in.get(c))
                    {
                        refuse(file, "truncated or garbled PNM header");
                    }
                }
            }
            else if (c != ' ' && c != '\t' && c != '\n' && c != '\r' && c != '\v' && c != '\f')
            {
                break;
            }
        }
        std::uint64_t v = 0;
        while (c >= '0' && c <= '9')
        {
            v = 10 * v + static_cast<std::uint64_t>(c - '0');
            if (v > 0x7FFFFFFFU || ++read > MAX_HEADER_BYTES || !in.get(c))
            {
                refuse(file, "truncated or garbled PNM header");
            }
        }
        if (v == 0)
        {
            refuse(file, "PNM header declares an invalid size");
        }
        if (c != ' ' && c != '\t' && c != '\n' && c != '\r' && c != '\v' && c != '\f')
        {
            refuse(file, "truncated or garbled PNM header");
        }
        side = static_cast<std::uint32_t>(v);
    }
    return {sides[0], sides[1], "PNM"};
}

/** BMP: a 14-byte file header, then the size in the DIB header. */
ImageHeader readBmp(std::istream& in, const std::string& file)
{
    std::array<unsigned char, 24> b{};  // bytes 2..25 of the file
    if (!readBytes(in, b.data(), 16))
    {
        refuse(file, "truncated BMP header");
    }
    const std::uint32_t dib = littleEndian(&b[12], 4);
    if (dib == 12)  // OS/2 BITMAPCOREHEADER: unsigned 16-bit sides
    {
        if (!readBytes(in, &b[16], 4))
        {
            refuse(file, "truncated BMP header");
        }
        const std::uint32_t w = littleEndian(&b[16], 2), h = littleEndian(&b[18], 2);
        if (w == 0 || h == 0)
        {
            refuse(file, "BMP header declares a zero size");
        }
        return {w, h, "BMP"};
    }
    if (dib < 16 || !readBytes(in, &b[16], 8))
    {
        refuse(file, "truncated or garbled BMP header");
    }
    // Signed 32-bit sides; a negative height means rows stored top-down.
    const auto w = static_cast<std::int32_t>(littleEndian(&b[16], 4));
    const auto h = static_cast<std::int32_t>(littleEndian(&b[20], 4));
    if (w <= 0 || h == 0 || h == std::numeric_limits<std::int32_t>::min())
    {
        refuse(file, "BMP header declares an invalid size");
    }
    return {static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h < 0 ? -h : h), "BMP"};
}
}  // namespace

ImageHeader readImageHeader(const std::string& file)
{
    std::ifstream in(file, std::ios::binary);
    if (!in)
    {
        refuse(file, "cannot open the file");
    }
    std::array<unsigned char, 8> magic{};
    if (!readBytes(in, magic.data(), 2))
    {
        refuse(file, "not a PNG, JPEG, BMP or PNM (PBM/PGM/PPM) file");
    }
    if (magic[0] == 0x89 && magic[1] == 'P')
    {
        constexpr std::array<unsigned char, 6> PNG_REST{'N', 'G', '\r', '\n', 0x1A, '\n'};
        if (readBytes(in, &magic[2], 6) && std::equal(PNG_REST.begin(), PNG_REST.end(), &magic[2]))
        {
            return readPng(in, file);
        }
    }
    else if (magic[0] == 0xFF && magic[1] == 0xD8)
    {
        return readJpeg(in, file);
    }
    else if (magic[0] == 'P' && magic[1] >= '1' && magic[1] <= '6')
    {
        return readPnm(in, file);
    }
    else if (magic[0] == 'B' && magic[1] == 'M')
    {
        return readBmp(in, file);
    }
    refuse(file, "not a PNG, JPEG, BMP or PNM (PBM/PGM/PPM) file");
}

}  // namespace emslam::io
