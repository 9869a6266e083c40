// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include <emslam/hwdrivers/PackedFrame.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

using emslam::hwdrivers::deinterleave;
using emslam::hwdrivers::interleave;
using emslam::hwdrivers::PackedFrameFormat;
using emslam::hwdrivers::PackedLayout;

namespace
{
/** A distinct, position-dependent pattern per channel. */
std::uint8_t pattern(unsigned int channel, int row, int col)
{
    return static_cast<std::uint8_t>((row * 7 + col * 3 + static_cast<int>(channel) * 85) & 0xFF);
}

/** Builds the packed frame byte by byte from the layout's definition (not
 * through interleave()), so that the test checks the documented layout. */
std::vector<std::uint8_t> packByHand(const PackedFrameFormat& f)
{
    std::vector<std::uint8_t> buf(f.bytesPerFrame());
    const unsigned int n = f.channels();
    for (int r = 0; r < static_cast<int>(f.height); ++r)
    {
        for (int c = 0; c < static_cast<int>(f.width); ++c)
        {
            for (unsigned int k = 0; k < n; ++k)
            {
                std::size_t idx = 0;
                if (f.layout == PackedLayout::PLANAR_8)
                {
                    idx = (static_cast<std::size_t>(k) * f.height + static_cast<std::size_t>(r)) *
                              f.width +
                          static_cast<std::size_t>(c);
                }
                else
                {
                    idx =
                        (static_cast<std::size_t>(r) * f.width + static_cast<std::size_t>(c)) * n +
                        k;
                }
                buf[idx] = pattern(k, r, c);
            }
        }
    }
    return buf;
}

void checkLayout(const PackedFrameFormat& f, unsigned int expected_channels)
{
    ASSERT_EQ(f.channels(), expected_channels);
    const auto buf = packByHand(f);
    const auto imgs = deinterleave(buf.data(), buf.size(), f);
    ASSERT_EQ(imgs.size(), expected_channels);
    for (unsigned int k = 0; k < expected_channels; ++k)
    {
        SCOPED_TRACE(k);
        ASSERT_EQ(imgs[k].type(), CV_8UC1);
        ASSERT_EQ(imgs[k].cols, static_cast<int>(f.width));
        ASSERT_EQ(imgs[k].rows, static_cast<int>(f.height));
        int mismatches = 0;
        for (int r = 0; r < imgs[k].rows; ++r)
        {
            for (int c = 0; c < imgs[k].cols; ++c)
            {
                mismatches += imgs[k].at<std::uint8_t>(r, c) != pattern(k, r, c) ? 1 : 0;
            }
        }
        EXPECT_EQ(mismatches, 0);
    }
    // The images own their data: the packed buffer may be reused at once.
    EXPECT_EQ(interleave(imgs, f), buf);
}
}  // namespace

TEST(PackedFrame, rgb24SplitsTheThreeByteChannels)
{
    PackedFrameFormat f;
    f.layout = PackedLayout::PIXEL_INTERLEAVED_24;
    f.width = 37;  // odd sizes: no hidden row padding assumption
    f.height = 11;
    EXPECT_EQ(f.bytesPerFrame(), 3U * 37U * 11U);
    checkLayout(f, 3);
}

TEST(PackedFrame, interleaved16SplitsTheTwoBytesOfEachPixel)
{
    PackedFrameFormat f;
    f.layout = PackedLayout::BYTE_INTERLEAVED_16;
    f.width = 640;
    f.height = 4;
    EXPECT_EQ(f.bytesPerFrame(), 2U * 640U * 4U);
    checkLayout(f, 2);
    // Byte 0 of the first pixel is channel 0, byte 1 is channel 1.
    const std::vector<std::uint8_t> two_pixels = {10, 20, 30, 40};
    PackedFrameFormat g = f;
    g.width = 2;
    g.height = 1;
    const auto imgs = deinterleave(two_pixels.data(), two_pixels.size(), g);
    EXPECT_EQ(imgs[0].at<std::uint8_t>(0, 0), 10);
    EXPECT_EQ(imgs[1].at<std::uint8_t>(0, 0), 20);
    EXPECT_EQ(imgs[0].at<std::uint8_t>(0, 1), 30);
    EXPECT_EQ(imgs[1].at<std::uint8_t>(0, 1), 40);
}

TEST(PackedFrame, planar8SplitsStackedImages)
{
    PackedFrameFormat f;
    f.layout = PackedLayout::PLANAR_8;
    f.width = 16;
    f.height = 9;
    f.planar_channels = 3;
    checkLayout(f, 3);
    f.planar_channels = 2;
    checkLayout(f, 2);
}

TEST(PackedFrame, wrongSizesThrow)
{
    PackedFrameFormat f;
    f.layout = PackedLayout::PIXEL_INTERLEAVED_24;
    f.width = 4;
    f.height = 2;
    std::vector<std::uint8_t> buf(f.bytesPerFrame() - 1);
    emslam::test::expectThrowContaining(
        [&] { deinterleave(buf.data(), buf.size(), f); }, {"23 bytes", "24 bytes"});
    f.width = 0;
    emslam::test::expectThrowContaining(
        [&] { deinterleave(buf.data(), 0, f); }, {"zero image size"});
    PackedFrameFormat p;
    p.layout = PackedLayout::PLANAR_8;
    p.width = p.height = 2;
    p.planar_channels = 4;
    emslam::test::expectThrowContaining(
        [&] { deinterleave(buf.data(), 16, p); }, {"2 or 3 images"});
    PackedFrameFormat g;
    g.layout = PackedLayout::BYTE_INTERLEAVED_16;
    g.width = g.height = 2;
    emslam::test::expectThrowContaining(
        [&] { interleave({cv::Mat::zeros(2, 2, CV_8UC1)}, g); }, {"packs 2 images, got 1"});
}

TEST(PackedFrame, layoutNamesRoundTrip)
{
    for (auto l :
         {PackedLayout::PIXEL_INTERLEAVED_24, PackedLayout::BYTE_INTERLEAVED_16,
          PackedLayout::PLANAR_8})
    {
        EXPECT_EQ(emslam::hwdrivers::packedLayoutFromString(emslam::hwdrivers::toString(l)), l);
    }
    emslam::test::expectThrowContaining(
        [] { emslam::hwdrivers::packedLayoutFromString("yuv422"); }, {"yuv422", "rgb24"});
}
