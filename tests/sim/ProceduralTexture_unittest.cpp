// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include <emslam/sim/ProceduralTexture.h>

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

using emslam::sim::ProceduralTexture;

TEST(ProceduralTexture, sameSeedSameTexelsOtherSeedOthers)
{
    for (const char* kind :
         {"noise", "bricks", "tiles", "repetitive", "poster", "wood", "gravel", "bush"})
    {
        const auto a = ProceduralTexture::generate(kind, 7, 128);
        const auto b = ProceduralTexture::generate(kind, 7, 128);
        const auto c = ProceduralTexture::generate(kind, 8, 128);
        ASSERT_EQ(a.size(), 128) << kind;
        EXPECT_EQ(cv::norm(a.image(), b.image(), cv::NORM_INF), 0.0) << kind;
        EXPECT_GT(cv::norm(a.image(), c.image(), cv::NORM_INF), 1.0) << kind;
        double mn = 0;
        double mx = 0;
        cv::minMaxLoc(a.image(), &mn, &mx);
        EXPECT_GE(mn, 0.0) << kind;
        EXPECT_LE(mx, 255.0) << kind;
    }
}

TEST(ProceduralTexture, hasEnoughGradientForStereo)
{
    for (const char* kind : {"noise", "bricks", "tiles", "gravel", "poster"})
    {
        const auto t = ProceduralTexture::generate(kind, 3, 256);
        cv::Mat gx;
        cv::Sobel(t.image(), gx, CV_32F, 1, 0);
        EXPECT_GT(cv::mean(cv::abs(gx))[0], 4.0) << kind;
    }
}

TEST(ProceduralTexture, bilinearSamplingWrapsAndInterpolates)
{
    const auto t = ProceduralTexture::generate("noise", 1, 64);
    const cv::Mat& im = t.image();
    // Texel centres return the texel; wrap-around by the texture size.
    EXPECT_FLOAT_EQ(t.sampleWrap(3.5, 5.5), im.at<float>(5, 3));
    EXPECT_NEAR(t.sampleWrap(3.5 + 64, 5.5 - 128), im.at<float>(5, 3), 1e-3);
    EXPECT_NEAR(t.sampleWrap(4.0, 5.5), 0.5F * (im.at<float>(5, 3) + im.at<float>(5, 4)), 1e-3);
}

TEST(ProceduralTexture, unknownKindIsNamed)
{
    emslam::test::expectThrowContaining(
        [] { ProceduralTexture::generate("marble", 1); }, {"marble", "noise"});
    EXPECT_THROW(ProceduralTexture::generate("noise", 1, 100), std::invalid_argument);
}
