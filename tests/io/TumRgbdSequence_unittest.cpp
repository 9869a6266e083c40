// SPDX-License-Identifier: BSD-3-Clause
#include "PngWithSize.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/TumRgbdSequence.h>

#include <mrpt/core/Clock.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

using emslam::io::TumRgbdSequence;
namespace fs = std::filesystem;

using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

namespace
{
constexpr int W = 24;
constexpr int H = 16;
constexpr double T0 = 1305031102.175304;

std::string stamp(double t)
{
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.6f", t);
    return buf;
}

/** Depth of frame i at pixel (u, v) [units of 1/5000 m]; 0 (no depth) on column 0. */
std::uint16_t depthAt(int i, int u, int v)
{
    return u == 0 ? 0 : static_cast<std::uint16_t>(5000 + 100 * i + 10 * u + v);
}

/** A TUM RGB-D folder: 5 colour images at 30 Hz; depth images 7 ms later,
 * except for colour image 3, which has none; ground truth at 100 Hz
 * (x = t - T0). Returns the folder. */
std::string writeSequence(const std::string& root)
{
    std::string dir = root + "/rgbd";
    fs::create_directories(dir + "/rgb");
    fs::create_directories(dir + "/depth");
    std::string rgb = "# color images\n# file: 'synthetic'\n# timestamp filename\n";
    std::string depth = "# depth maps\n# file: 'synthetic'\n# timestamp filename\n";
    for (int i = 0; i < 5; i++)
    {
        const double tc = T0 + i / 30.0;
        const double td = tc + 0.007;
        rgb += stamp(tc) + " rgb/" + stamp(tc) + ".png\n";
        if (i != 3)
        {
            depth += stamp(td) + " depth/" + stamp(td) + ".png\n";
        }
        cv::imwrite(
            dir + "/rgb/" + stamp(tc) + ".png",
            cv::Mat(H, W, CV_8UC3, cv::Scalar(10 * i, 20 * i, 30 * i)));
        cv::Mat d(H, W, CV_16UC1);
        for (int v = 0; v < H; v++)
        {
            for (int u = 0; u < W; u++)
            {
                d.at<std::uint16_t>(v, u) = depthAt(i, u, v);
            }
        }
        cv::imwrite(dir + "/depth/" + stamp(td) + ".png", d);
    }
    writeFile(dir + "/rgb.txt", rgb);
    writeFile(dir + "/depth.txt", depth);
    std::string gt = "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
    for (int k = -5; k < 20; k++)
    {
        const double t = T0 + 0.01 * k + 0.002;
        char line[128];
        std::snprintf(line, sizeof(line), "%.4f %.4f 1.0 2.0 0 0 0 1\n", t, 0.01 * k + 0.002);
        gt += line;
    }
    writeFile(dir + "/groundtruth.txt", gt);
    return dir;
}
}  // namespace

TEST(TumRgbdSequence, readsSyntheticSequence)
{
    const std::string dir = writeSequence(emslam::test::makeTempDir("tum_ok"));
    TumRgbdSequence s;
    s.open(dir);
    ASSERT_EQ(s.size(), 4U);  // colour image 3 has no depth image
    EXPECT_EQ(s.unassociatedCount(), 1U);
    EXPECT_EQ(s.imageWidth(), static_cast<unsigned>(W));
    EXPECT_NEAR(s.timestamp(3), T0 + 4 / 30.0, 1e-6);
    EXPECT_NEAR(s.depthTimestamp(3) - s.timestamp(3), 0.007, 1e-6);
    ASSERT_TRUE(s.hasGroundTruth());
    EXPECT_EQ(s.framesWithoutGroundTruth(), 0U);

    const auto f = s.frame(1);
    const auto& obs = *f.obs;
    EXPECT_EQ(obs.sensorLabel, "RGBD");
    EXPECT_NEAR(mrpt::Clock::toDouble(obs.timestamp), T0 + 1 / 30.0, 1e-6);
    EXPECT_TRUE(obs.hasIntensityImage);
    EXPECT_TRUE(obs.intensityImage.isColor());
    EXPECT_EQ(obs.intensityImage.getWidth(), static_cast<unsigned>(W));
    EXPECT_TRUE(obs.hasRangeImage);
    EXPECT_TRUE(obs.range_is_depth);
    EXPECT_FALSE(obs.hasPoints3D);
    EXPECT_FLOAT_EQ(obs.rangeUnits, 1.0f / 5000.0f);
    ASSERT_EQ(obs.rangeImage.rows(), H);
    ASSERT_EQ(obs.rangeImage.cols(), W);
    for (const auto& [u, v] : {std::pair{0, 0}, std::pair{5, 7}, std::pair{W - 1, H - 1}})
    {
        EXPECT_EQ(obs.rangeImage(v, u), depthAt(1, u, v));
    }
    // TUM default intrinsics, image size from the images.
    EXPECT_DOUBLE_EQ(obs.cameraParams.fx(), 525.0);
    EXPECT_DOUBLE_EQ(obs.cameraParams.fy(), 525.0);
    EXPECT_DOUBLE_EQ(obs.cameraParams.cx(), 319.5);
    EXPECT_DOUBLE_EQ(obs.cameraParams.cy(), 239.5);
    EXPECT_EQ(obs.cameraParams.ncols, static_cast<unsigned>(W));
    EXPECT_DOUBLE_EQ(obs.cameraParamsIntensity.fx(), 525.0);
    EXPECT_TRUE(obs.doDepthAndIntensityCamerasCoincide());

    // sensorPose takes MRPT's range-scan frame (x = depth, y = -(u-cx)/fx*depth,
    // z = -(v-cy)/fy*depth) to the optical frame (x right, y down, z forward).
    const double d = 2.0, u = 400.0, v = 100.0;
    const mrpt::math::TPoint3D p_sensor(d, -(u - 319.5) / 525.0 * d, -(v - 239.5) / 525.0 * d);
    const auto p_cam = obs.sensorPose.composePoint(p_sensor);
    EXPECT_NEAR(p_cam.x, (u - 319.5) / 525.0 * d, 1e-12);
    EXPECT_NEAR(p_cam.y, (v - 239.5) / 525.0 * d, 1e-12);
    EXPECT_NEAR(p_cam.z, d, 1e-12);

    // Nearest GT row (100 Hz, 2 ms after the grid): x = t_gt - T0.
    ASSERT_TRUE(f.ground_truth.has_value());
    EXPECT_NEAR(f.ground_truth->x(), 0.032, 1e-9);
    EXPECT_NEAR(f.ground_truth->z(), 2.0, 1e-12);

    // The observation serializes and reads back.
    mrpt::io::CMemoryStream buf;
    auto arch = mrpt::serialization::archiveFrom(buf);
    arch << obs;
    buf.Seek(0);
    const auto back = arch.ReadObject<mrpt::obs::CObservation3DRangeScan>();
    ASSERT_TRUE(back);
    EXPECT_EQ(back->rangeImage(7, 5), depthAt(1, 5, 7));
    EXPECT_TRUE(back->hasIntensityImage);
}

TEST(TumRgbdSequence, customIntrinsicsAndTolerances)
{
    const std::string dir = writeSequence(emslam::test::makeTempDir("tum_opts"));
    TumRgbdSequence s;
    s.intrinsics.setIntrinsicParamsFromValues(517.3, 516.5, 318.6, 255.3);
    // Colour image 3: the depth images 26 and 40 ms away are taken by colour images 2 and 4.
    s.max_association_dt = 0.05;
    s.gt_max_dt = 0.0005;  // GT rows are 2 ms away: none associated
    s.sensor_label = "KINECT";
    s.open(dir);
    EXPECT_EQ(s.size(), 4U);
    EXPECT_EQ(s.unassociatedCount(), 1U);
    EXPECT_EQ(s.framesWithoutGroundTruth(), 4U);
    const auto f = s.frame(0);
    EXPECT_DOUBLE_EQ(f.obs->cameraParams.fx(), 517.3);
    EXPECT_DOUBLE_EQ(f.obs->cameraParams.cy(), 255.3);
    EXPECT_EQ(f.obs->sensorLabel, "KINECT");
    EXPECT_FALSE(f.ground_truth.has_value());

    TumRgbdSequence tight;
    tight.max_association_dt = 0.005;  // depth is 7 ms after colour: no pair
    expectThrowContaining([&] { tight.open(dir); }, {"no colour image has a depth image"});
}

TEST(TumRgbdSequence, groundTruthIsOptional)
{
    const std::string dir = writeSequence(emslam::test::makeTempDir("tum_nogt"));
    fs::remove(dir + "/groundtruth.txt");
    TumRgbdSequence s;
    s.open(dir);
    EXPECT_FALSE(s.hasGroundTruth());
    EXPECT_FALSE(s.frame(0).ground_truth.has_value());
}

TEST(TumRgbdSequence, badInputThrows)
{
    const std::string root = emslam::test::makeTempDir("tum_bad");
    TumRgbdSequence s;
    expectThrowContaining([&] { s.open(root + "/nope"); }, {root + "/nope", "does not exist"});

    const std::string dir = writeSequence(root);
    fs::rename(dir + "/depth.txt", dir + "/depth.bak");
    expectThrowContaining([&] { s.open(dir); }, {dir + "/depth.txt"});
    fs::rename(dir + "/depth.bak", dir + "/depth.txt");

    writeFile(dir + "/rgb.txt", "# c\n1305031102.17 rgb/a.png\nnot-a-time rgb/b.png\n");
    expectThrowContaining([&] { s.open(dir); }, {dir + "/rgb.txt:3"});
    writeFile(dir + "/rgb.txt", "100.0 rgb/a.png\n");
    expectThrowContaining([&] { s.open(dir); }, {"no colour image has a depth image"});
}

TEST(TumRgbdSequence, badImagesThrow)
{
    const std::string dir = writeSequence(emslam::test::makeTempDir("tum_images"));
    const std::string rgb1 = dir + "/rgb/" + stamp(T0 + 1 / 30.0) + ".png";
    const std::string depth2 = dir + "/depth/" + stamp(T0 + 2 / 30.0 + 0.007) + ".png";
    const std::string rgb4 = dir + "/rgb/" + stamp(T0 + 4 / 30.0) + ".png";  // frame 3
    writeFile(rgb1, "garbage bytes instead of a PNG");
    cv::imwrite(depth2, cv::Mat(H, W, CV_8UC1, cv::Scalar(3)));  // 8-bit depth
    cv::imwrite(rgb4, cv::Mat(H, W + 4, CV_8UC3, cv::Scalar(3)));
    TumRgbdSequence s;
    s.open(dir);
    EXPECT_NO_THROW(s.frame(0));
    expectThrowContaining([&] { s.frame(1); }, {rgb1, "Cannot read"});
    expectThrowContaining([&] { s.frame(2); }, {depth2, "16-bit"});
    expectThrowContaining([&] { s.frame(3); }, {rgb4, "mismatch"});

    // First colour and depth images of different sizes: open() fails.
    const std::string rgb0 = dir + "/rgb/" + stamp(T0) + ".png";
    cv::imwrite(rgb0, cv::Mat(H + 2, W, CV_8UC3, cv::Scalar(3)));
    expectThrowContaining([&] { s.open(dir); }, {"mismatch", rgb0});
    fs::remove(rgb0);
    expectThrowContaining([&] { s.open(dir); }, {rgb0, "missing"});
}

namespace
{
/** A TUM list with one "timestamp file" line per stamp, after a comment line. */
std::string listOf(std::initializer_list<std::string> stamps, const std::string& sub)
{
    std::string text = "# timestamp filename\n";
    for (const auto& t : stamps)
    {
        text += t + " " + sub + "/" + t + ".png\n";
    }
    return text;
}
}  // namespace

// Both lists were sorted: a repeated stamp gave two frames with one time.
TEST(TumRgbdSequence, repeatedStampIsRefused)
{
    const std::string dir = writeSequence(emslam::test::makeTempDir("tum_dup"));
    const std::string t1 = stamp(T0 + 1 / 30.0);
    writeFile(dir + "/rgb.txt", listOf({stamp(T0), t1, t1}, "rgb"));
    expectThrowContaining(
        [&] { TumRgbdSequence().open(dir); },
        {dir + "/rgb.txt:4: timestamp '" + t1 +
         "' repeats the previous one (line 3): timestamps must increase strictly"});
}

TEST(TumRgbdSequence, stampGoingBackwardsIsRefused)
{
    const std::string dir = writeSequence(emslam::test::makeTempDir("tum_back"));
    const std::string d0 = stamp(T0 + 0.007), d1 = stamp(T0 + 1 / 30.0 + 0.007);
    writeFile(dir + "/depth.txt", listOf({d1, d0}, "depth"));
    expectThrowContaining(
        [&] { TumRgbdSequence().open(dir); },
        {dir + "/depth.txt:3: timestamp '" + d0 + "' is before the previous one '" + d1 +
         "' (line 2): timestamps must increase strictly"});
}

// 0 was taken as a valid time (MRPT's "no time"), INT64_MAX seconds too.
TEST(TumRgbdSequence, zeroOrAbsurdStampInTheMiddleIsRefused)
{
    const std::string dir = writeSequence(emslam::test::makeTempDir("tum_absurd"));
    for (const std::string bad :
         {"0", "0.000000", "-1.5", "9223372036854775807", "4102444800.000001", "1e300", "inf",
          "nan"})
    {
        writeFile(dir + "/rgb.txt", listOf({stamp(T0), bad, stamp(T0 + 2 / 30.0)}, "rgb"));
        expectThrowContaining(
            [&] { TumRgbdSequence().open(dir); },
            {dir + "/rgb.txt:3: timestamp '" + bad +
             "' is not a plausible time: expected seconds since 1970-01-01 UTC in [1e-07, "
             "4102444800] (MRPT reads 0 as \"no time\"; the upper bound is 2100-01-01)"});
    }
}

TEST(TumRgbdSequence, hugeImageIsRefusedFromItsHeader)
{
    const std::string dir = writeSequence(emslam::test::makeTempDir("tum_huge"));
    const std::string depth1 = dir + "/depth/" + stamp(T0 + 1 / 30.0 + 0.007) + ".png";
    emslam::test::writePngDeclaring(depth1, 30000, 30000);
    TumRgbdSequence s;
    s.open(dir);
    expectThrowContaining(
        [&] { s.frame(1); },
        {"Image '" + depth1 +
         "' is 30000x30000 (PNG header): over the limit of 67108864 pixels (8192x8192) and "
         "65535 per side; not decoded"});
    emslam::test::writePngDeclaring(depth1, 640, 480);
    expectThrowContaining(
        [&] { s.frame(1); },
        {"Image size mismatch: '" + depth1 + "' is 640x480, expected 24x16 (first frame)"});
}
