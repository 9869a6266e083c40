// SPDX-License-Identifier: BSD-3-Clause
#include "SyntheticStereo.h"
#include "TestData.h"

#include <emslam/stereo/StereoMatcher.h>

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>
#include <vector>

using emslam::stereo::StereoMatcher;

namespace
{
double median(std::vector<double> v)
{
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

// Depth error of a fronto-parallel plane: returns {median |dz|, fraction within tol, density}.
struct PlaneResult
{
    double median_abs_err{0}, inlier_fraction{0}, density{0};
};

PlaneResult reconstructPlane(const StereoMatcher::TParameters& p, double z_true)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, z_true, 7, l, r);
    const auto f = StereoMatcher(p).compute(l, r, cam);
    PlaneResult res;
    std::vector<double> err;
    std::size_t inliers = 0;
    // Disparity-quantisation-level noise: sigma_z = z^2 / (f B) * 0.25 px.
    const double tol = 3.0 * z_true * z_true / (200.0 * 0.10) * 0.25;
    for (const auto& pt : f.points)
    {
        err.push_back(std::abs(pt.z - z_true));
        inliers += err.back() < tol;
    }
    if (!err.empty())
    {
        res.median_abs_err = median(err);
        res.inlier_fraction = static_cast<double>(inliers) / err.size();
    }
    res.density = f.density();
    return res;
}
}  // namespace

TEST(StereoMatcher, frontoParallelPlaneReconstructsAtItsDepth)
{
    StereoMatcher::TParameters p;
    for (const double z : {1.3, 2.3, 4.1})
    {
        const auto r = reconstructPlane(p, z);
        // SGBM's parabolic sub-pixel fit is biased toward whole pixels
        // ("pixel locking"): up to ~0.25 px at fractional disparities.
        const double dz_per_px = z * z / (200.0 * 0.10);
        EXPECT_LT(r.median_abs_err, 0.3 * dz_per_px) << "z=" << z;
        EXPECT_GT(r.inlier_fraction, 0.97) << "z=" << z;
        // Everything but the left band where the right camera sees nothing.
        EXPECT_GT(r.density, 0.6) << "z=" << z;
    }
    // A whole-pixel disparity (16 px at 1.25 m) is recovered almost exactly.
    const auto r = reconstructPlane(p, 1.25);
    EXPECT_LT(r.median_abs_err, 0.05 * 1.25 * 1.25 / 20.0);
}

// subpixel = false: every disparity is a whole pixel, the nearest to the
// truth, so the depth is off by the rounding, up to half a pixel's depth step.
TEST(StereoMatcher, wholePixelDisparitiesRoundToTheNearestPixel)
{
    StereoMatcher::TParameters p;
    p.subpixel = false;
    const auto cam = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    const double z = 2.3;  // d = 8.70 px: 9 px, 2.22 m
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, z, 7, l, r);
    const auto f = StereoMatcher(p).compute(l, r, cam);
    ASSERT_GT(f.points.size(), 10000u);
    std::size_t at_nine = 0;
    for (int v = 0; v < f.disparity.rows; ++v)
    {
        for (int u = 0; u < f.disparity.cols; ++u)
        {
            const float d = f.disparity.at<float>(v, u);
            ASSERT_EQ(d, std::floor(d)) << "at (" << u << ", " << v << ")";
            at_nine += d == 9.0f;
        }
    }
    EXPECT_GT(static_cast<double>(at_nine), 0.95 * static_cast<double>(f.points.size()));
    std::vector<double> z_err;
    for (const auto& pt : f.points)
    {
        z_err.push_back(pt.z - z);
    }
    // The whole-pixel depth 20 / 9 = 2.222 m, 0.078 m short of the truth
    // (with sub-pixel disparities the median error is under 0.08 m x 0.3).
    EXPECT_NEAR(median(z_err), 20.0 / 9.0 - z, 1e-3);
}

TEST(StereoMatcher, blockMatchingAlsoReconstructsThePlane)
{
    StereoMatcher::TParameters p;
    p.algorithm = "bm";
    p.block_size = 9;
    const auto r = reconstructPlane(p, 2.3);
    EXPECT_LT(r.median_abs_err, 0.3 * 2.3 * 2.3 / 20.0);
    EXPECT_GT(r.inlier_fraction, 0.95);
    EXPECT_GT(r.density, 0.5);
}

TEST(StereoMatcher, pointsAreInTheLeftCameraFrameAndMatchTheirPixels)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, 2.0, 3, l, r);
    const auto f = StereoMatcher().compute(l, r, cam);
    ASSERT_FALSE(f.empty());
    ASSERT_EQ(f.points.size(), f.pixels.size());
    EXPECT_EQ(static_cast<std::size_t>(cv::countNonZero(f.valid)), f.points.size());
    for (std::size_t i = 0; i < f.points.size(); i += 97)
    {
        const auto& p = f.points[i];
        const double u = 200.0 * p.x / p.z + cam.leftCamera.cx();
        const double v = 200.0 * p.y / p.z + cam.leftCamera.cy();
        EXPECT_NEAR(u, f.pixels[i].u, 1e-3);
        EXPECT_NEAR(v, f.pixels[i].v, 1e-3);
        EXPECT_GT(f.disparity.at<float>(f.pixels[i].v, f.pixels[i].u), 0.0f);
    }
}

TEST(StereoMatcher, imageScaleHalvesTheFrameAndKeepsDepth)
{
    StereoMatcher::TParameters p;
    p.image_scale = 0.5;
    p.num_disparities = 32;
    const auto cam = emslam::test::idealStereoCamera(640, 480, 400.0, 0.10);
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, 2.0, 11, l, r);
    const auto f = StereoMatcher(p).compute(l, r, cam);
    EXPECT_EQ(f.intensity.cols, 320);
    EXPECT_EQ(f.intensity.rows, 240);
    EXPECT_EQ(f.camera.leftCamera.ncols, 320u);
    EXPECT_NEAR(f.camera.leftCamera.fx(), 200.0, 1e-9);
    EXPECT_NEAR(f.camera.leftCamera.cx(), (319.5 + 0.5) * 0.5 - 0.5, 1e-9);
    std::vector<double> z;
    for (const auto& pt : f.points)
    {
        z.push_back(pt.z);
    }
    ASSERT_GT(z.size(), 10000u);
    EXPECT_NEAR(median(z), 2.0, 0.02);
}

TEST(StereoMatcher, maxRangeDropsFarPoints)
{
    StereoMatcher::TParameters p;
    p.max_range = 2.0;
    const auto r = reconstructPlane(p, 4.1);
    EXPECT_EQ(r.density, 0.0);
}

TEST(StereoMatcher, emptyAndMismatchedImagesThrow)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    StereoMatcher m;
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, 2.0, 1, l, r);
    EXPECT_THROW(m.compute(cv::Mat(), r, cam), std::exception);
    EXPECT_THROW(m.compute(l, r(cv::Rect(0, 0, 300, 240)).clone(), cam), std::exception);
    const auto wrong = emslam::test::idealStereoCamera(640, 480, 200.0, 0.10);
    EXPECT_THROW(m.compute(l, r, wrong), std::exception);
    const auto no_baseline = emslam::test::idealStereoCamera(320, 240, 200.0, 0.0);
    EXPECT_THROW(m.compute(l, r, no_baseline), std::exception);
}

TEST(StereoMatcher, textureLessPairGivesNoPoints)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    const cv::Mat flat(240, 320, CV_8UC1, cv::Scalar(128));
    const auto f = StereoMatcher().compute(flat, flat, cam);
    EXPECT_LT(f.density(), 0.01);
}

TEST(StereoMatcherParameters, loadsNonDefaultValuesFromIni)
{
    mrpt::config::CConfigFileMemory c(std::string(R"(
[StereoMatcher]
algorithm = bm
image_scale = 0.5
num_disparities = 48
min_disparity = 2
block_size = 11
uniqueness_ratio = 15
speckle_window_size = 50
speckle_range = 3
lr_max_diff = -1
texture_threshold = 20
pre_filter_cap = 40
p1_per_pixel = 4
p2_per_pixel = 20
min_range = 0.5
max_range = 20
subpixel = false
)"));
    StereoMatcher::TParameters p;
    p.loadFromConfigFile(c, "StereoMatcher");
    EXPECT_EQ(p.algorithm, "bm");
    EXPECT_EQ(p.image_scale, 0.5);
    EXPECT_EQ(p.num_disparities, 48);
    EXPECT_EQ(p.min_disparity, 2);
    EXPECT_EQ(p.block_size, 11);
    EXPECT_EQ(p.uniqueness_ratio, 15);
    EXPECT_EQ(p.speckle_window_size, 50);
    EXPECT_EQ(p.speckle_range, 3);
    EXPECT_EQ(p.lr_max_diff, -1);
    EXPECT_EQ(p.texture_threshold, 20);
    EXPECT_EQ(p.pre_filter_cap, 40);
    EXPECT_EQ(p.p1_per_pixel, 4);
    EXPECT_EQ(p.p2_per_pixel, 20);
    EXPECT_EQ(p.min_range, 0.5);
    EXPECT_EQ(p.max_range, 20.0);
    EXPECT_FALSE(p.subpixel);
}

TEST(StereoMatcherParameters, saveAndReloadRoundTrips)
{
    StereoMatcher::TParameters p;
    p.algorithm = "sgbm_3way";
    p.image_scale = 0.25;
    p.num_disparities = 80;
    p.block_size = 7;
    p.max_range = 30.5;
    p.p1_per_pixel = 2;
    p.p2_per_pixel = 9;
    mrpt::config::CConfigFileMemory c;
    p.saveToConfigFile(c, "StereoMatcher");
    const mrpt::config::CConfigFileMemory reparsed(c.getContent());
    StereoMatcher::TParameters q;
    q.loadFromConfigFile(reparsed, "StereoMatcher");
    EXPECT_EQ(q.algorithm, p.algorithm);
    EXPECT_EQ(q.image_scale, p.image_scale);
    EXPECT_EQ(q.num_disparities, p.num_disparities);
    EXPECT_EQ(q.block_size, p.block_size);
    EXPECT_EQ(q.max_range, p.max_range);
    EXPECT_EQ(q.min_range, p.min_range);
    EXPECT_EQ(q.p1_per_pixel, p.p1_per_pixel);
    EXPECT_EQ(q.p2_per_pixel, p.p2_per_pixel);
}

TEST(StereoMatcherParameters, invalidValuesThrow)
{
    const char* bad[] = {
        "algorithm = census", "image_scale = 0", "image_scale = 1.5", "num_disparities = 0",
        "block_size = 4", "max_range = 0.1", "uniqueness_ratio = 101", "p2_per_pixel = 8",
        "p1_per_pixel = -1",
        // Values that overflowed OpenCV's fixed point or SGBM's penalties:
        "block_size = 99999", "block_size = 257", "num_disparities = 2000",
        "min_disparity = 200000000", "lr_max_diff = 2147483647", "p2_per_pixel = 100000"};
    for (const char* line : bad)
    {
        mrpt::config::CConfigFileMemory c(std::string("[StereoMatcher]\n") + line + "\n");
        StereoMatcher::TParameters p;
        EXPECT_THROW(p.loadFromConfigFile(c, "StereoMatcher"), std::exception) << line;
    }
}

TEST(StereoMatcherParameters, shippedConfigsLoad)
{
    const std::string dir = emslam::test::sourceDir() + "/config/stereo";
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(dir))
    {
        if (e.path().extension() == ".ini")
        {
            mrpt::config::CConfigFile c(e.path().string());
            StereoMatcher::TParameters p;
            EXPECT_NO_THROW(p.loadFromConfigFile(c, "StereoMatcher")) << e.path();
            files.push_back(e.path().string());
        }
    }
    EXPECT_FALSE(files.empty());
}

// The keyframes' dense clouds may run on several threads with one matcher:
// OpenCV's SGBM reuses its buffers between calls, so concurrent calls must
// give exactly what the same calls give one after the other.
TEST(StereoMatcher, concurrentCallsGiveTheSerialDisparities)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    const std::array<double, 2> depths{0.8, 1.6};
    std::array<cv::Mat, 2> lefts, rights, serial;
    const StereoMatcher matcher;
    for (std::size_t k = 0; k < depths.size(); ++k)
    {
        emslam::test::renderFrontoParallelPlane(
            cam, depths[k], static_cast<std::uint32_t>(11 + k), lefts[k], rights[k]);
        // Independent noise patches: small regions of wrong disparities for
        // the speckle filter, which works in the matcher's buffer.
        cv::RNG rng(static_cast<std::uint64_t>(5 + k));
        for (int y = 8; y + 12 < lefts[k].rows; y += 20)
        {
            for (int x = 48; x + 12 < lefts[k].cols; x += 20)
            {
                rng.fill(lefts[k](cv::Rect(x, y, 12, 12)), cv::RNG::UNIFORM, 0, 255);
                rng.fill(rights[k](cv::Rect(x - 20, y, 12, 12)), cv::RNG::UNIFORM, 0, 255);
            }
        }
        serial[k] = matcher.compute(lefts[k], rights[k], cam).disparity;
        ASSERT_GT(cv::countNonZero(serial[k]), 1000);
    }
    std::array<int, 2> differing{0, 0};
    auto run = [&](std::size_t k)
    {
        for (int i = 0; i < 24; ++i)
        {
            const cv::Mat d = matcher.compute(lefts[k], rights[k], cam).disparity;
            differing[k] += cv::countNonZero(d != serial[k]) > 0;
        }
    };
    std::thread other(run, 1);
    run(0);
    other.join();
    EXPECT_EQ(differing[0], 0);
    EXPECT_EQ(differing[1], 0);
}
