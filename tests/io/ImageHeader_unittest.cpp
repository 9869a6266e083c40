// SPDX-License-Identifier: BSD-3-Clause
#include "PngWithSize.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/ImageHeader.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

using emslam::io::readImageHeader;
using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

namespace
{
std::string readBytes(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
}  // namespace

TEST(ImageHeader, readsTheSizeOfEveryFormatOpenCvWrites)
{
    const std::string dir = emslam::test::makeTempDir("image_header");
    const cv::Mat grey(23, 37, CV_8UC1, cv::Scalar(90));
    const cv::Mat colour(23, 37, CV_8UC3, cv::Scalar(1, 2, 3));
    const cv::Mat depth(23, 37, CV_16UC1, cv::Scalar(5000));
    const struct
    {
        const char* name;
        const cv::Mat* image;
        const char* format;
    } cases[] = {{"g.png", &grey, "PNG"},   {"d.png", &depth, "PNG"}, {"c.jpg", &colour, "JPEG"},
                 {"g.jpg", &grey, "JPEG"},  {"g.pgm", &grey, "PNM"},  {"d.pgm", &depth, "PNM"},
                 {"c.ppm", &colour, "PNM"}, {"g.pbm", &grey, "PNM"},  {"c.bmp", &colour, "BMP"}};
    for (const auto& c : cases)
    {
        const std::string file = dir + "/" + c.name;
        ASSERT_TRUE(cv::imwrite(file, *c.image)) << c.name;
        const auto h = readImageHeader(file);
        EXPECT_EQ(h.width, 37U) << c.name;
        EXPECT_EQ(h.height, 23U) << c.name;
        EXPECT_EQ(std::string(h.format), c.format) << c.name;
    }
}

TEST(ImageHeader, readsHeadersWrittenByHand)
{
    const std::string dir = emslam::test::makeTempDir("image_header_hand");
    // PNM comments and any blanks between the numbers.
    writeFile(dir + "/a.pgm", "P5\n# made by hand\n# 1 2\n 640\t# width\n\n480\n255\n");
    EXPECT_EQ(readImageHeader(dir + "/a.pgm").width, 640U);
    EXPECT_EQ(readImageHeader(dir + "/a.pgm").height, 480U);
    writeFile(dir + "/b.pbm", "P1 3 2 0 1 0 1 0 1\n");
    EXPECT_EQ(readImageHeader(dir + "/b.pbm").height, 2U);
    // JPEG: fill bytes, a standalone marker and a comment segment before SOF2.
    const std::string jpeg(
        "\xFF\xD8\xFF\xFF\xFF\x01\xFF\xFE\x00\x05"
        "abc\xFF\xC2\x00\x0B\x08\x01\xE0\x02\x80\x01\x01\x11\x00",
        26);
    writeFile(dir + "/c.jpg", jpeg);
    EXPECT_EQ(readImageHeader(dir + "/c.jpg").width, 640U);
    EXPECT_EQ(readImageHeader(dir + "/c.jpg").height, 480U);
    // BMP stored top-down: a negative height.
    std::string bmp(54, '\0');
    bmp[0] = 'B';
    bmp[1] = 'M';
    bmp[14] = 40;
    bmp[18] = 0x20;  // width 800
    bmp[19] = 0x03;
    bmp[22] = '\x38';  // height -200
    bmp[23] = bmp[24] = bmp[25] = '\xFF';
    writeFile(dir + "/d.bmp", bmp);
    EXPECT_EQ(readImageHeader(dir + "/d.bmp").width, 800U);
    EXPECT_EQ(readImageHeader(dir + "/d.bmp").height, 200U);
}

// A 30000 x 30000 PNG is a few hundred bytes here: its header is all that is read.
TEST(ImageHeader, hugeDeclaredSizeIsReadWithoutDecoding)
{
    const std::string file = emslam::test::makeTempDir("image_header_huge") + "/huge.png";
    emslam::test::writePngDeclaring(file, 30000, 30000);
    EXPECT_LT(readBytes(file).size(), 200U);
    const auto h = readImageHeader(file);
    EXPECT_EQ(h.width, 30000U);
    EXPECT_EQ(h.height, 30000U);
}

TEST(ImageHeader, garbledHeadersThrowNamingTheFile)
{
    const std::string dir = emslam::test::makeTempDir("image_header_bad");
    const auto expectRefused =
        [&](const std::string& name, const std::string& bytes, const std::string& reason)
    {
        writeFile(dir + "/" + name, bytes);
        expectThrowContaining(
            [&] { readImageHeader(dir + "/" + name); },
            {"Cannot read image '" + dir + "/" + name + "': " + reason});
    };
    expectRefused(
        "text.png", "garbage, not a png", "not a PNG, JPEG, BMP or PNM (PBM/PGM/PPM) file");
    expectRefused("empty.png", "", "not a PNG, JPEG, BMP or PNM (PBM/PGM/PPM) file");
    expectRefused("gif.png", "GIF89a\x01\x00\x01\x00", "not a PNG, JPEG, BMP or PNM");
    emslam::test::writePngDeclaring(dir + "/ok.png", 16, 16);
    const std::string png = readBytes(dir + "/ok.png");
    expectRefused("cut.png", png.substr(0, 20), "PNG without an IHDR header chunk");
    std::string zero = png;
    zero[16] = zero[17] = zero[18] = zero[19] = '\0';
    expectRefused("zero.png", zero, "PNG header declares an invalid size");
    expectRefused(
        "sos.jpg", std::string("\xFF\xD8\xFF\xDA\x00\x02", 6),
        "JPEG without a frame header before its image data");
    expectRefused(
        "cut.jpg", std::string("\xFF\xD8\xFF\xE0\x00\x10JFIF", 10),
        "JPEG with a truncated or garbled segment before its frame header");
    expectRefused("cut.pgm", "P5\n640", "truncated or garbled PNM header");
    expectRefused("neg.pgm", "P5 -640 480 255\n", "PNM header declares an invalid size");
    expectRefused("big.pgm", "P5 99999999999 480 255\n", "truncated or garbled PNM header");
    expectRefused("cut.bmp", "BM\x01\x02", "truncated BMP header");
    expectThrowContaining(
        [&] { readImageHeader(dir + "/none.png"); },
        {"Cannot read image '" + dir + "/none.png': cannot open the file"});
}
