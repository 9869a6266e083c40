// SPDX-License-Identifier: BSD-3-Clause
#include "SyntheticStereo.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/KittiSequence.h>
#include <emslam/stereo/SparseStereoMatcher.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/stereo/StereoFrontEnd.h>
#include <emslam/stereo/StereoMatcher.h>
#include <emslam/util/CpuDispatch.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

using emslam::stereo::PixelCoord;
using emslam::stereo::SparseStereoMatcher;
using emslam::stereo::StereoMatcher;

namespace
{
constexpr double F = 200.0, B = 0.10;

std::vector<PixelCoord> grid(int width, int height, int step)
{
    std::vector<PixelCoord> px;
    for (int v = 0; v < height; v += step)
    {
        for (int u = 0; u < width; u += step)
        {
            px.push_back({static_cast<std::uint16_t>(u), static_cast<std::uint16_t>(v)});
        }
    }
    return px;
}

SparseStereoMatcher::TParameters planeParams()
{
    SparseStereoMatcher::TParameters p;
    p.num_disparities = 64;
    p.min_range = 0.3;
    p.max_range = 20;
    return p;
}
}  // namespace

// A textured plane at a known depth: the disparity is known exactly (f B / z,
// sub-pixel), so every point's depth and its (x, y) can be checked.
TEST(SparseStereoMatcher, frontoParallelPlaneAtKnownDepths)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, F, B);
    const auto pixels = grid(320, 240, 5);
    for (const double z : {1.5, 2.5, 4.0})
    {
        cv::Mat l, r;
        emslam::test::renderFrontoParallelPlane(cam, z, 11, l, r);
        const auto f = SparseStereoMatcher(planeParams()).compute(l, r, cam, pixels);
        std::vector<double> disparity_err;
        for (std::size_t i = 0; i < f.size(); ++i)
        {
            const auto& p = f.points[i];
            disparity_err.push_back(std::abs(F * B / p.z - F * B / z));
            // The point lies on the ray of its pixel.
            EXPECT_NEAR(p.x / p.z * F + cam.leftCamera.cx(), f.pixels[i].u, 1e-3);
            EXPECT_NEAR(p.y / p.z * F + cam.leftCamera.cy(), f.pixels[i].v, 1e-3);
            EXPECT_EQ(f.valid.at<std::uint8_t>(f.pixels[i].v, f.pixels[i].u), 255);
        }
        // Pixels near the left border have no right partner, those near every
        // border no full window: the rest (about 85 %) should all match.
        const double kept = static_cast<double>(f.size()) / static_cast<double>(pixels.size());
        std::nth_element(
            disparity_err.begin(), disparity_err.begin() + disparity_err.size() / 2,
            disparity_err.end());
        const double median = disparity_err[disparity_err.size() / 2];
        const double worst = *std::max_element(disparity_err.begin(), disparity_err.end());
        std::printf(
            "z = %.1f m (d = %.2f px): %.1f %% kept, median |dd| %.3f px, max %.3f px\n", z,
            F * B / z, 100 * kept, median, worst);
        EXPECT_GT(kept, 0.75);
        EXPECT_LT(median, 0.1);
        EXPECT_LT(worst, 1.0);
        EXPECT_EQ(cv::countNonZero(f.valid), static_cast<int>(f.size()));
        EXPECT_TRUE(f.disparity.empty());
    }
}

// subpixel = false (from [StereoMatcher]): the best whole pixel, no
// interpolation: every disparity is an integer, the nearest to the truth
// (7.41 px) for most pixels, the other neighbour (8) where the SAD minimum
// falls there (and a rare false match, as with sub-pixel disparities).
TEST(SparseStereoMatcher, wholePixelDisparitiesWithoutSubpixel)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, F, B);
    StereoMatcher::TParameters dense;
    dense.subpixel = false;
    auto p = SparseStereoMatcher::fromStereo(dense);
    EXPECT_FALSE(p.subpixel);
    p.num_disparities = 64;
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, 2.7, 11, l, r);  // d = 7.41 px
    const auto f = SparseStereoMatcher(p).compute(l, r, cam, grid(320, 240, 5));
    ASSERT_GT(f.size(), 1000u);
    std::size_t at_seven = 0, at_eight = 0;
    for (const auto& pt : f.points)
    {
        const double d = F * B / pt.z;
        ASSERT_NEAR(d, std::round(d), 1e-3);
        at_seven += std::abs(d - 7.0) < 1e-3;
        at_eight += std::abs(d - 8.0) < 1e-3;
    }
    const double n = static_cast<double>(f.size());
    EXPECT_GT(static_cast<double>(at_seven), 0.8 * n);
    EXPECT_GT(static_cast<double>(at_seven + at_eight), 0.99 * n);
}

// A pattern that repeats every 6 px inside the search range: every disparity
// 6 px apart costs the same, so the uniqueness test must refuse (almost) all.
TEST(SparseStereoMatcher, repetitivePatternIsRejectedByUniqueness)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, F, B);
    cv::Mat l(240, 320, CV_8UC1);
    for (int v = 0; v < l.rows; ++v)
    {
        for (int u = 0; u < l.cols; ++u)
        {
            l.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(u % 6 < 3 ? 60 : 190);
        }
    }
    cv::Mat r;
    const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, -8, 0, 1, 0);
    cv::warpAffine(l, r, shift, l.size(), cv::INTER_NEAREST, cv::BORDER_REFLECT);
    // Pixels whose whole search range lies in the image (near the left
    // border the range is cut, and a cut range may hold a single period).
    std::vector<PixelCoord> pixels;
    for (const PixelCoord& p : grid(320, 240, 4))
    {
        if (p.u >= 80)
        {
            pixels.push_back(p);
        }
    }
    const auto f = SparseStereoMatcher(planeParams()).compute(l, r, cam, pixels);
    EXPECT_EQ(f.size(), 0u);
}

// Unrelated images: a best cost exists everywhere, but the left-right check
// and the uniqueness test drop most pixels (a smooth texture still gives
// chance minima, as it does to SGBM: the egomotion's LWO is what rejects them).
TEST(SparseStereoMatcher, unrelatedImagesLoseMostPoints)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, F, B);
    cv::Mat l, r, l2, r2;
    emslam::test::renderFrontoParallelPlane(cam, 2.0, 1, l, r);
    emslam::test::renderFrontoParallelPlane(cam, 2.0, 2, l2, r2);
    const auto pixels = grid(320, 240, 4);
    const SparseStereoMatcher m(planeParams());
    const auto related = m.compute(l, r, cam, pixels);
    const auto unrelated = m.compute(l, r2, cam, pixels);
    std::printf(
        "of %zu pixels: %zu kept from a stereo pair, %zu from unrelated images\n", pixels.size(),
        related.size(), unrelated.size());
    EXPECT_LT(unrelated.size(), related.size() / 2);
}

// Pixels on the border or outside the image are skipped, never read out of bounds.
TEST(SparseStereoMatcher, borderAndOutsidePixelsAreSkipped)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, F, B);
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, 2.0, 3, l, r);
    const std::vector<PixelCoord> pixels{{0, 0},   {319, 239}, {2, 120},  {160, 1},
                                         {317, 5}, {400, 10},  {10, 300}, {65535, 65535}};
    const auto f = SparseStereoMatcher(planeParams()).compute(l, r, cam, pixels);
    EXPECT_EQ(f.size(), 0u);
}

TEST(SparseStereoMatcher, badInputsThrow)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, F, B);
    const SparseStereoMatcher m(planeParams());
    const cv::Mat img(240, 320, CV_8UC1, cv::Scalar(9));
    EXPECT_THROW(m.compute(cv::Mat(), img, cam, {}), std::exception);
    EXPECT_THROW(m.compute(img, cv::Mat(200, 320, CV_8UC1), cam, {}), std::exception);
    EXPECT_THROW(m.compute(cv::Mat(240, 320, CV_8UC3), img, cam, {}), std::exception);
    const auto small = emslam::test::idealStereoCamera(160, 120, F, B);
    EXPECT_THROW(m.compute(img, img, small, {}), std::exception);
}

TEST(SparseStereoMatcher, parametersComeFromStereoAtFullResolution)
{
    StereoMatcher::TParameters dense;
    dense.image_scale = 0.5;
    dense.num_disparities = 60;  // SGBM searches 64 at half size: 128 at full size
    dense.min_disparity = 3;
    dense.sparse_block_size = 7;
    dense.max_range = 30;
    const auto s = SparseStereoMatcher::fromStereo(dense);
    EXPECT_EQ(s.num_disparities, 128);
    EXPECT_EQ(s.min_disparity, 6);
    EXPECT_EQ(s.block_size, 7);
    EXPECT_EQ(s.max_range, 30);
    EXPECT_NO_THROW(s.validate());

    dense.sparse_block_size = 8;
    emslam::test::expectThrowContaining(
        [&] { dense.validate(); },
        {"[StereoMatcher] sparse_block_size = 8: must be odd, in [3, 15]"});
    SparseStereoMatcher::TParameters bad = s;
    bad.block_size = 17;
    EXPECT_THROW(SparseStereoMatcher{bad}, std::invalid_argument);
}

// Real images: at KITTI's strong-gradient pixels the sparse disparities agree
// with OpenCV's 8-path SGBM wherever both have one.
TEST(SparseStereoMatcher, agreesWithSgbmOnKitti)
{
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    StereoMatcher::TParameters p;
    p.algorithm = "sgbm_hh";
    p.num_disparities = 128;
    p.max_range = 80;
    p.min_range = 1;
    emslam::stereo::StereoFrontEnd dense_front(p);
    const auto obs = emslam::io::KittiSequence(seq_dir).frame(10).obs;
    const auto dense = dense_front.process(*obs);

    // Every local maximum of |d/dx| above 40 in its 9x9 window: edges where a
    // row search is well posed.
    cv::Mat gx;
    cv::Sobel(dense.intensity, gx, CV_32F, 1, 0, 3);
    gx = cv::abs(gx);
    cv::Mat mx;
    cv::dilate(gx, mx, cv::Mat::ones(9, 9, CV_8UC1));
    std::vector<PixelCoord> pixels;
    for (int v = 0; v < gx.rows; ++v)
    {
        for (int u = 0; u < gx.cols; ++u)
        {
            if (gx.at<float>(v, u) > 40 && gx.at<float>(v, u) == mx.at<float>(v, u))
            {
                pixels.push_back({static_cast<std::uint16_t>(u), static_cast<std::uint16_t>(v)});
            }
        }
    }
    const auto sparse = SparseStereoMatcher(SparseStereoMatcher::fromStereo(p))
                            .compute(dense.intensity, dense.intensity, dense.camera, {});
    EXPECT_TRUE(sparse.empty());  // no pixels asked, none given

    emslam::stereo::StereoFrontEnd sparse_front(
        [&]
        {
            auto q = p;
            q.sparse_at_features = true;
            return q;
        }());
    sparse_front.setPixelSelector([&](const cv::Mat&) { return pixels; });
    const auto s = sparse_front.process(*obs);
    std::size_t both = 0, agree = 0;
    std::vector<double> diffs;
    for (std::size_t i = 0; i < s.size(); ++i)
    {
        const float d_dense = dense.disparity.at<float>(s.pixels[i].v, s.pixels[i].u);
        if (d_dense <= 0)
        {
            continue;
        }
        ++both;
        const double fb = s.camera.leftCamera.fx() * emslam::stereo::baselineOf(s.camera);
        agree += std::abs(fb / s.points[i].z - d_dense) < 1.0;
        diffs.push_back(fb / s.points[i].z - d_dense);
    }
    std::sort(diffs.begin(), diffs.end());
    std::printf(
        "sparse - dense disparity: q10 %.3f q25 %.3f median %.3f q75 %.3f q90 %.3f\n",
        diffs[diffs.size() / 10], diffs[diffs.size() / 4], diffs[diffs.size() / 2],
        diffs[3 * diffs.size() / 4], diffs[9 * diffs.size() / 10]);
    std::printf(
        "KITTI 06 frame 10: %zu edge pixels, %zu sparse points, %zu also dense, %.1f %% within "
        "1 px\n",
        pixels.size(), s.size(), both, 100.0 * static_cast<double>(agree) / both);
    EXPECT_GT(s.size(), pixels.size() / 2);
    EXPECT_GT(both, s.size() / 2);
    EXPECT_GT(static_cast<double>(agree), 0.9 * static_cast<double>(both));
}

// The row search's costs run in blocks of 32 disparities on AVX2 where the
// CPU has it, of 16 on the baseline (SSE2), and by a portable loop below 16:
// integer sums, so every disparity must be the same to the bit, also where
// the range is not a multiple of 32 or 16 (near the image borders).
TEST(SparseStereoMatcher, avx2AndBaselineCostsGiveTheSameDisparities)
{
    emslam::util::setBaselineOnly(false);
    if (!emslam::util::avx2Enabled())
    {
        GTEST_SKIP() << "this CPU (or EMSLAM_SIMD) runs the baseline loops only";
    }
    const auto cam = emslam::test::idealStereoCamera(320, 240, F, B);
    const auto pixels = grid(320, 240, 3);
    for (const int nd : {64, 70})
    {
        auto p = planeParams();
        p.num_disparities = nd;
        cv::Mat l, r;
        emslam::test::renderFrontoParallelPlane(cam, 2.0, 11, l, r);
        const auto wide = SparseStereoMatcher(p).compute(l, r, cam, pixels);
        emslam::util::setBaselineOnly(true);
        const auto base = SparseStereoMatcher(p).compute(l, r, cam, pixels);
        emslam::util::setBaselineOnly(false);
        ASSERT_GT(wide.points.size(), 1000u) << nd;
        ASSERT_EQ(wide.points.size(), base.points.size()) << nd;
        for (std::size_t i = 0; i < wide.points.size(); ++i)
        {
            ASSERT_EQ(wide.pixels[i].u, base.pixels[i].u);
            ASSERT_EQ(wide.pixels[i].v, base.pixels[i].v);
            ASSERT_EQ(wide.points[i].z, base.points[i].z) << nd << " " << i;
            ASSERT_EQ(wide.points[i].x, base.points[i].x);
        }
    }
}
