// SPDX-License-Identifier: BSD-3-Clause
#include "SyntheticStereo.h"

#include <emslam/egomotion/GlmFeatureExtractor.h>
#include <emslam/stereo/StereoMatcher.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <set>
#include <utility>

using emslam::egomotion::FeatureList;
using emslam::egomotion::GlmFeatureExtractor;
using emslam::stereo::StereoFrame;

namespace
{
/** A frame around `img` whose valid pixels (mask != 0, all if empty) carry
 * the point (u, v, 1) so that tests can tell which point a feature took. */
StereoFrame frameFromImage(const cv::Mat& img, const cv::Mat& mask = cv::Mat())
{
    StereoFrame f;
    f.intensity = img;
    f.valid = mask.empty() ? cv::Mat(img.size(), CV_8UC1, cv::Scalar(255)) : mask;
    for (int v = 0; v < img.rows; ++v)
    {
        for (int u = 0; u < img.cols; ++u)
        {
            if (f.valid.at<uint8_t>(v, u) != 0)
            {
                f.points.emplace_back(
                    static_cast<float>(u), static_cast<float>(v), static_cast<float>(1.0));
                f.pixels.push_back({static_cast<std::uint16_t>(u), static_cast<std::uint16_t>(v)});
            }
        }
    }
    return f;
}

/** Seeded white noise, lightly blurred: many distinct gradient maxima. */
cv::Mat randomTexture(int w, int h, unsigned seed, double blur_sigma)
{
    cv::Mat noise(h, w, CV_32F);
    cv::RNG rng(seed);
    rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
    if (blur_sigma > 0)
    {
        cv::GaussianBlur(noise, noise, cv::Size(), blur_sigma);
    }
    cv::normalize(noise, noise, 10, 245, cv::NORM_MINMAX);
    cv::Mat out;
    noise.convertTo(out, CV_8U);
    return out;
}

/** The definition, by brute force: (u, v) pixels whose |grad I| is > 0 and
 * strictly above every other pixel of the window -W/2..W-1-W/2 (clipped to
 * the image), excluding the 1-pixel border. */
std::set<std::pair<int, int>> bruteForceStrictMaxima(const cv::Mat& img, int w)
{
    cv::Mat gx, gy, mag;
    cv::Sobel(img, gx, CV_32F, 1, 0, 3);
    cv::Sobel(img, gy, CV_32F, 0, 1, 3);
    cv::magnitude(gx, gy, mag);
    std::set<std::pair<int, int>> out;
    const int lo = -(w / 2), hi = w - 1 - w / 2;
    for (int v = 1; v < img.rows - 1; ++v)
    {
        for (int u = 1; u < img.cols - 1; ++u)
        {
            const float m = mag.at<float>(v, u);
            bool strict = m > 0;
            for (int dv = lo; strict && dv <= hi; ++dv)
            {
                for (int du = lo; strict && du <= hi; ++du)
                {
                    const int uu = u + du, vv = v + dv;
                    if ((du != 0 || dv != 0) && uu >= 0 && vv >= 0 && uu < img.cols &&
                        vv < img.rows && mag.at<float>(vv, uu) >= m)
                    {
                        strict = false;
                    }
                }
            }
            if (strict)
            {
                out.emplace(u, v);
            }
        }
    }
    return out;
}

GlmFeatureExtractor extractor(int w, float min_gradient = 0)
{
    GlmFeatureExtractor::TParameters p;
    p.window_size = w;
    p.min_gradient = min_gradient;
    return GlmFeatureExtractor(p);
}
}  // namespace

TEST(GlmFeatureExtractor, plateauOfEqualMaximaYieldsNoFeature)
{
    // A vertical step edge: columns 29 and 30 share the same |grad I| on
    // every row, a plateau of maxima (strictly above all other pixels).
    cv::Mat img(60, 60, CV_8UC1, cv::Scalar(50));
    img.colRange(30, 60).setTo(150);
    for (int w : {3, 4, 8})
    {
        EXPECT_TRUE(extractor(w).extract(frameFromImage(img)).empty()) << "W=" << w;
    }
    // A linear ramp: |grad I| is constant everywhere, one big plateau.
    cv::Mat ramp(40, 40, CV_8UC1);
    for (int v = 0; v < ramp.rows; ++v)
    {
        for (int u = 0; u < ramp.cols; ++u)
        {
            ramp.at<uint8_t>(v, u) = static_cast<uint8_t>(40 + 2 * u + v);
        }
    }
    EXPECT_TRUE(extractor(3).extract(frameFromImage(ramp)).empty());
    // A flat image has no gradient at all.
    EXPECT_TRUE(
        extractor(3).extract(frameFromImage(cv::Mat(30, 30, CV_8UC1, cv::Scalar(9)))).empty());
}

TEST(GlmFeatureExtractor, featuresAreExactlyTheStrictWindowMaxima)
{
    const cv::Mat img = randomTexture(97, 71, 1234, 1.0);
    const StereoFrame frame = frameFromImage(img);
    for (int w : {2, 3, 4, 5, 8, 9})
    {
        const auto expected = bruteForceStrictMaxima(img, w);
        std::set<std::pair<int, int>> got;
        for (const auto& f : extractor(w).extract(frame))
        {
            got.emplace(f.u, f.v);
        }
        ASSERT_FALSE(expected.empty()) << "W=" << w;
        EXPECT_EQ(got, expected) << "W=" << w;
    }
}

TEST(GlmFeatureExtractor, minGradientDropsWeakMaxima)
{
    const StereoFrame frame = frameFromImage(randomTexture(80, 60, 5, 1.5));
    const auto all = extractor(8).extract(frame);
    ASSERT_FALSE(all.empty());
    std::vector<float> mags;
    for (const auto& f : all)
    {
        mags.push_back(f.gradient_magnitude);
    }
    std::sort(mags.begin(), mags.end());
    const float thr = mags[mags.size() / 2];
    const auto strong = extractor(8, thr).extract(frame);
    const auto n_expected = static_cast<std::size_t>(
        std::count_if(mags.begin(), mags.end(), [&](float m) { return m >= thr; }));
    EXPECT_EQ(strong.size(), n_expected);
    for (const auto& f : strong)
    {
        EXPECT_GE(f.gradient_magnitude, thr);
    }
}

TEST(GlmFeatureExtractor, densityDecreasesAsTheWindowGrows)
{
    // A real stereo frame: textured plane 2 m away, 10 px of disparity.
    const auto cam = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, 2.0, 11, l, r);
    const StereoFrame frame = emslam::stereo::StereoMatcher().compute(l, r, cam);
    ASSERT_GT(frame.size(), 10000U);
    cv::Mat index(frame.intensity.size(), CV_32S, cv::Scalar(-1));
    for (std::size_t i = 0; i < frame.size(); ++i)
    {
        index.at<int>(frame.pixels[i].v, frame.pixels[i].u) = static_cast<int>(i);
    }

    std::size_t previous = frame.size() + 1;
    for (int w : {4, 8, 12, 16})
    {
        const auto feats = extractor(w).extract(frame);
        EXPECT_GT(feats.size(), 0U) << "W=" << w;
        EXPECT_LT(feats.size(), previous) << "W=" << w;
        previous = feats.size();
        for (const auto& f : feats)
        {
            ASSERT_NE(frame.valid.at<uint8_t>(f.v, f.u), 0);
            const int idx = index.at<int>(f.v, f.u);
            ASSERT_GE(idx, 0);
            const auto& pt = frame.points[static_cast<std::size_t>(idx)];
            EXPECT_EQ(f.point.x, pt.x);
            EXPECT_EQ(f.point.y, pt.y);
            EXPECT_EQ(f.point.z, pt.z);
        }
    }
}

TEST(GlmFeatureExtractor, featuresOnlyWhereValidWithTheirPoint)
{
    const cv::Mat img = randomTexture(120, 90, 77, 1.0);
    // Invalid 10x10 blocks in a checkerboard.
    cv::Mat mask(img.size(), CV_8UC1, cv::Scalar(0));
    for (int v = 0; v < img.rows; ++v)
    {
        for (int u = 0; u < img.cols; ++u)
        {
            mask.at<uint8_t>(v, u) = ((u / 10 + v / 10) % 2 == 0) ? 255 : 0;
        }
    }
    const auto ex = extractor(6);
    const auto masked = ex.extract(frameFromImage(img, mask));
    const auto full = ex.extract(frameFromImage(img));
    ASSERT_FALSE(masked.empty());

    // Validity filters the maxima of the whole image; it does not change them.
    std::set<std::pair<int, int>> expected, got;
    for (const auto& f : full)
    {
        if (mask.at<uint8_t>(f.v, f.u) != 0)
        {
            expected.emplace(f.u, f.v);
        }
    }
    for (const auto& f : masked)
    {
        EXPECT_NE(mask.at<uint8_t>(f.v, f.u), 0);
        EXPECT_EQ(f.point.x, static_cast<float>(f.u));
        EXPECT_EQ(f.point.y, static_cast<float>(f.v));
        got.emplace(f.u, f.v);
    }
    EXPECT_EQ(got, expected);
    EXPECT_LT(masked.size(), full.size());
}

TEST(GlmFeatureExtractor, gradientAngleAndMagnitudeOnRamps)
{
    // With W = 1 the window is the pixel itself, so every interior pixel of a
    // ramp 128 + a(u-16) + b(v-16) is a feature with Sobel gradient (8a, 8b).
    for (const auto& [a, b] : std::vector<std::pair<int, int>>{
             {2, 0}, {0, 2}, {-2, 0}, {0, -2}, {2, 1}, {-1, 2}, {-2, -2}, {1, -2}})
    {
        cv::Mat ramp(32, 32, CV_8UC1);
        for (int v = 0; v < ramp.rows; ++v)
        {
            for (int u = 0; u < ramp.cols; ++u)
            {
                ramp.at<uint8_t>(v, u) = static_cast<uint8_t>(128 + a * (u - 16) + b * (v - 16));
            }
        }
        const auto feats = extractor(1).extract(frameFromImage(ramp));
        ASSERT_EQ(feats.size(), 30U * 30U) << "a=" << a << " b=" << b;
        const float angle = std::atan2(static_cast<float>(b), static_cast<float>(a));
        for (const auto& f : feats)
        {
            EXPECT_NEAR(f.gradient_angle, angle, 1e-6f);
            EXPECT_GT(f.gradient_angle, -static_cast<float>(M_PI));
            EXPECT_NEAR(f.gradient_magnitude, 8.0f * std::hypot(a, b), 1e-3f);
        }
    }
}

TEST(GlmFeatureExtractor, emptyFrameAndBadParameters)
{
    EXPECT_TRUE(extractor(8).extract(frameFromImage(cv::Mat(2, 2, CV_8UC1))).empty());
    const StereoFrame frame = frameFromImage(randomTexture(20, 20, 3, 1.0));
    EXPECT_ANY_THROW(extractor(0).extract(frame));
    EXPECT_ANY_THROW(extractor(8, -1.0f).extract(frame));
}

// locate() is extract() without the 3D points: where every pixel has a
// point, the same pixels in the same (raster) order; with a mask, extract()
// keeps exactly the located pixels that the mask allows.
TEST(GlmFeatureExtractor, locateFindsThePixelsExtractKeeps)
{
    const cv::Mat img = randomTexture(160, 120, 21, 1.5);
    for (const int w : {3, 8})
    {
        GlmFeatureExtractor::TParameters p;
        p.window_size = w;
        p.min_gradient = 20.0f;
        const GlmFeatureExtractor glm(p);
        const auto located = glm.locate(img);
        const FeatureList all = glm.extract(frameFromImage(img));
        ASSERT_EQ(located.size(), all.size()) << "W = " << w;
        ASSERT_GT(located.size(), 50U);
        for (std::size_t i = 0; i < all.size(); ++i)
        {
            EXPECT_EQ(located[i].u, all[i].u);
            EXPECT_EQ(located[i].v, all[i].v);
        }
        // A mask of the left half: extract() keeps the located pixels there.
        cv::Mat mask = cv::Mat::zeros(img.size(), CV_8UC1);
        mask.colRange(0, 80).setTo(255);
        const FeatureList left = glm.extract(frameFromImage(img, mask));
        const auto in_left =
            std::count_if(located.begin(), located.end(), [](const auto& px) { return px.u < 80; });
        EXPECT_EQ(static_cast<std::ptrdiff_t>(left.size()), in_left);
    }
    EXPECT_TRUE(GlmFeatureExtractor().locate(cv::Mat(2, 2, CV_8UC1, cv::Scalar(0))).empty());
    EXPECT_THROW(GlmFeatureExtractor().locate(cv::Mat(10, 10, CV_8UC3)), std::exception);
}

// The gradient maps locate() hands out serve extract() of the same image
// (a copy of it too) and give its features exactly; those of another image,
// or of other parameters, are not used: the features are still the image's own.
TEST(GlmFeatureExtractor, gradientsOfLocateServeOnlyTheirOwnImage)
{
    const cv::Mat img = randomTexture(160, 120, 22, 1.5);
    const cv::Mat other = randomTexture(160, 120, 23, 1.5);
    const auto same = [](const FeatureList& a, const FeatureList& b)
    {
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i)
        {
            EXPECT_EQ(a[i].u, b[i].u);
            EXPECT_EQ(a[i].v, b[i].v);
            EXPECT_EQ(a[i].gradient_angle, b[i].gradient_angle);
            EXPECT_EQ(a[i].gradient_magnitude, b[i].gradient_magnitude);
        }
    };
    GlmFeatureExtractor::TParameters p;
    p.window_size = 8;
    p.min_gradient = 10.0f;
    const GlmFeatureExtractor glm(p);
    std::shared_ptr<const GlmFeatureExtractor::Gradients> maps;
    const auto located = glm.locate(img, maps);
    ASSERT_NE(maps, nullptr);
    ASSERT_GT(located.size(), 50U);
    const FeatureList own = glm.extract(frameFromImage(img));
    same(glm.extract(frameFromImage(img.clone()), maps.get()), own);
    same(glm.extract(frameFromImage(other), maps.get()), glm.extract(frameFromImage(other)));
    p.window_size = 3;
    const GlmFeatureExtractor glm3(p);
    same(glm3.extract(frameFromImage(img), maps.get()), glm3.extract(frameFromImage(img)));
    EXPECT_NE(glm3.extract(frameFromImage(img)).size(), own.size());
}
