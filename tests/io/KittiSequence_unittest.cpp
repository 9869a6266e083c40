// SPDX-License-Identifier: BSD-3-Clause
#include "PngWithSize.h"
#include "SyntheticKitti.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/KittiSequence.h>
#include <emslam/stereo/StereoCalibration.h>

#include <mrpt/core/Clock.h>
#include <mrpt/poses/CPose3D.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

using emslam::io::KittiSequence;
namespace fs = std::filesystem;

using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

using emslam::test::kittiPixel;
using emslam::test::writeKittiSequence;
constexpr int W = emslam::test::KITTI_W;
constexpr int H = emslam::test::KITTI_H;
constexpr double FX = emslam::test::KITTI_FX;
constexpr double BASELINE = emslam::test::KITTI_BASELINE;

namespace
{
std::string frameName(const std::string& dir, const char* sub, int i)
{
    return emslam::test::kittiFrameName(dir, sub, i);
}
}  // namespace

TEST(KittiSequence, readsRealSequence06)
{
    EMSLAM_REQUIRE_TEST_DATA(seq, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    KittiSequence s(seq, poses);
    ASSERT_EQ(s.size(), 51U);
    EXPECT_EQ(s.imageWidth(), 1226U);
    EXPECT_EQ(s.imageHeight(), 370U);
    EXPECT_NEAR(emslam::stereo::baselineOf(s.calibration()), 0.5372, 1e-4);
    EXPECT_NEAR(s.calibration().leftCamera.fx(), 707.0912, 1e-9);
    ASSERT_TRUE(s.hasGroundTruth());
    EXPECT_NEAR(s.groundTruth(0).translation().norm(), 0.0, 1e-9);
    EXPECT_NEAR(s.groundTruth(50).z(), 59.83857, 1e-5);  // the last pose of the excerpt

    for (const std::size_t i : {std::size_t(0), std::size_t(50)})
    {
        const auto f = s.frame(i);
        ASSERT_TRUE(f.obs);
        EXPECT_TRUE(f.obs->hasImageRight);
        EXPECT_FALSE(f.obs->hasImageDisparity);
        EXPECT_EQ(f.obs->sensorLabel, "STEREO");
        EXPECT_EQ(f.obs->imageLeft.getWidth(), 1226U);
        EXPECT_EQ(f.obs->imageRight.getHeight(), 370U);
        EXPECT_FALSE(f.obs->imageLeft.isColor());
        EXPECT_TRUE(f.obs->areImagesRectified());
        EXPECT_NEAR(f.obs->rightCameraPose.x(), 0.5372, 1e-4);
        EXPECT_DOUBLE_EQ(f.t, KittiSequence::DEFAULT_TIME_OFFSET + s.sequenceTime(i));
        EXPECT_NEAR(mrpt::Clock::toDouble(f.obs->timestamp), f.t, 1e-6);
        ASSERT_TRUE(f.ground_truth.has_value());
    }
    EXPECT_NEAR(s.sequenceTime(1), 0.1044989, 1e-9);
}

TEST(KittiSequence, readsSyntheticSequence)
{
    const std::string root = emslam::test::makeTempDir("kitti_ok");
    const std::string dir = writeKittiSequence(root, 5);
    KittiSequence s;
    EXPECT_FALSE(s.isOpen());
    s.sensor_label = "CAM";
    s.time_offset = 1000.0;
    s.open(dir, root + "/poses.txt");
    ASSERT_TRUE(s.isOpen());
    ASSERT_EQ(s.size(), 5U);
    EXPECT_EQ(s.imageWidth(), static_cast<unsigned>(W));
    EXPECT_EQ(s.imageHeight(), static_cast<unsigned>(H));
    EXPECT_NEAR(emslam::stereo::baselineOf(s.calibration()), BASELINE, 1e-12);
    EXPECT_DOUBLE_EQ(s.timestamp(3), 1000.3);

    const auto f = s.frame(3);
    EXPECT_EQ(f.obs->sensorLabel, "CAM");
    EXPECT_NEAR(mrpt::Clock::toDouble(f.obs->timestamp), 1000.3, 1e-6);
    const auto L = f.obs->imageLeft.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
    const auto R = f.obs->imageRight.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
    for (const auto& [u, v] : {std::pair{0, 0}, std::pair{W - 1, H - 1}, std::pair{17, 9}})
    {
        EXPECT_EQ(L.at<std::uint8_t>(v, u), kittiPixel(3, 0, u, v));
        EXPECT_EQ(R.at<std::uint8_t>(v, u), kittiPixel(3, 1, u, v));
    }
    const auto cam = f.obs->getStereoCameraParams();
    EXPECT_DOUBLE_EQ(cam.leftCamera.fx(), FX);
    EXPECT_EQ(cam.leftCamera.ncols, static_cast<unsigned>(W));
    ASSERT_TRUE(f.ground_truth.has_value());
    const mrpt::poses::CPose3D expected(0, 0, 3, 0, 0.03, 0);  // yaw, pitch (about y), roll
    EXPECT_NEAR((*f.ground_truth - expected).translation().norm(), 0.0, 1e-8);
    EXPECT_NEAR(f.ground_truth->pitch(), 0.03, 1e-8);
    // Rotation re-orthonormalized.
    const auto Rm = f.ground_truth->getRotationMatrix();
    for (int r = 0; r < 3; r++)
    {
        for (int c = 0; c < 3; c++)
        {
            const double dot = Rm(r, 0) * Rm(c, 0) + Rm(r, 1) * Rm(c, 1) + Rm(r, 2) * Rm(c, 2);
            EXPECT_NEAR(dot, r == c ? 1.0 : 0.0, 1e-12);
        }
    }

    // Without poses: no ground truth.
    KittiSequence s2(dir);
    EXPECT_FALSE(s2.hasGroundTruth());
    EXPECT_FALSE(s2.frame(0).ground_truth.has_value());
    EXPECT_ANY_THROW(s2.groundTruth(0));
    EXPECT_ANY_THROW(s2.frame(5));
}

TEST(KittiSequence, missingFolderThrows)
{
    const std::string root = emslam::test::makeTempDir("kitti_nofolder");
    expectThrowContaining(
        [&] { KittiSequence s(root + "/nope"); }, {root + "/nope", "does not exist"});
    fs::create_directories(root + "/seq/image_0");
    expectThrowContaining([&] { KittiSequence s(root + "/seq"); }, {"image_1"});
}

TEST(KittiSequence, missingOrGarbledCalibrationThrows)
{
    const std::string root = emslam::test::makeTempDir("kitti_calib");
    const std::string dir = writeKittiSequence(root, 3);
    const std::string calib = dir + "/calib.txt";
    std::ifstream in(calib);
    std::string p0, p1;
    std::getline(in, p0);
    std::getline(in, p1);
    in.close();

    writeFile(calib, p0 + "\n");  // no P1
    expectThrowContaining([&] { KittiSequence s(dir); }, {calib, "P1"});

    writeFile(calib, p0 + "\nP1: 50 0 20 -12.5 0 50 abc 0 0 0 1 0\n");
    expectThrowContaining([&] { KittiSequence s(dir); }, {calib});

    writeFile(calib, p0 + "\nP1: 50 0 20 -12.5 0 50\n");  // too few numbers
    expectThrowContaining([&] { KittiSequence s(dir); }, {calib});

    fs::remove(calib);
    expectThrowContaining([&] { KittiSequence s(dir); }, {calib});
}

TEST(KittiSequence, sizeMismatchThrows)
{
    const std::string root = emslam::test::makeTempDir("kitti_size");
    const std::string dir = writeKittiSequence(root, 3);
    // First pair: left/right differ -> open() fails.
    cv::imwrite(frameName(dir, "image_1", 0), cv::Mat(H, W + 2, CV_8UC1, cv::Scalar(9)));
    expectThrowContaining(
        [&] { KittiSequence s(dir); }, {"mismatch", frameName(dir, "image_1", 0)});
    // A later frame differs from the first -> frame() fails.
    cv::imwrite(frameName(dir, "image_1", 0), cv::Mat(H, W, CV_8UC1, cv::Scalar(9)));
    cv::imwrite(frameName(dir, "image_0", 2), cv::Mat(H + 1, W, CV_8UC1, cv::Scalar(9)));
    KittiSequence s(dir);
    EXPECT_NO_THROW(s.frame(1));
    expectThrowContaining([&] { s.frame(2); }, {"mismatch", frameName(dir, "image_0", 2)});
}

// A 30000 x 30000 PNG (875 KB on disk, here a few hundred bytes) was decoded
// in full (900 MB, 5 s) before its size was compared; now its header decides.
TEST(KittiSequence, hugeImageIsRefusedFromItsHeader)
{
    const std::string root = emslam::test::makeTempDir("kitti_huge");
    const std::string dir = writeKittiSequence(root, 3);
    const std::string left1 = frameName(dir, "image_0", 1);
    emslam::test::writePngDeclaring(left1, 30000, 30000);
    KittiSequence s(dir);
    expectThrowContaining(
        [&] { s.frame(1); },
        {"Image '" + left1 +
         "' is 30000x30000 (PNG header): over the limit of 67108864 pixels (8192x8192) and "
         "65535 per side; not decoded"});
    // Within the limits but not the first frame's size: refused from the header as well.
    emslam::test::writePngDeclaring(left1, 8000, 8000);
    expectThrowContaining(
        [&] { s.frame(1); },
        {"Image size mismatch: '" + left1 + "' is 8000x8000, expected 40x24 (first frame, calib)"});
    emslam::test::writePngDeclaring(left1, 65536, 1);
    expectThrowContaining([&] { s.frame(1); }, {left1, "65536x1", "65535 per side"});
    // The first pair, whose size nothing else gives.
    for (const char* sub : {"image_0", "image_1"})
    {
        emslam::test::writePngDeclaring(frameName(dir, sub, 0), 30000, 30000);
    }
    expectThrowContaining(
        [&] { KittiSequence t(dir); },
        {"Image '" + frameName(dir, "image_0", 0) + "' is 30000x30000 (PNG header)",
         "not decoded"});
}

TEST(KittiSequence, unreadableImageThrows)
{
    const std::string root = emslam::test::makeTempDir("kitti_garbage");
    const std::string dir = writeKittiSequence(root, 3);
    writeFile(frameName(dir, "image_1", 2), "this is not a PNG file");
    KittiSequence s(dir);
    expectThrowContaining([&] { s.frame(2); }, {frameName(dir, "image_1", 2), "Cannot read"});
    writeFile(frameName(dir, "image_0", 0), std::string(100, '\x42'));
    expectThrowContaining([&] { KittiSequence t(dir); }, {frameName(dir, "image_0", 0)});
}

TEST(KittiSequence, missingImageOrTimesMismatchThrows)
{
    const std::string root = emslam::test::makeTempDir("kitti_missing");
    const std::string dir = writeKittiSequence(root, 3);
    fs::rename(frameName(dir, "image_1", 1), dir + "/image_1/000009.png");
    expectThrowContaining([&] { KittiSequence s(dir); }, {frameName(dir, "image_1", 1)});
    fs::remove(dir + "/image_1/000009.png");
    expectThrowContaining([&] { KittiSequence s(dir); }, {"times.txt", "3 frames", "2 PNG"});

    const std::string dir2 = writeKittiSequence(emslam::test::makeTempDir("kitti_times"), 3);
    writeFile(dir2 + "/times.txt", "0.0\n0.1\nzero.two\n");
    expectThrowContaining([&] { KittiSequence s(dir2); }, {"times.txt:3"});
    // Were accepted and gave NaN or 0 timestamps in the rawlog.
    for (const char* bad : {"nan", "inf", "1e300", "-0.5"})
    {
        writeFile(dir2 + "/times.txt", std::string("0.0\n0.1\n") + bad + "\n");
        expectThrowContaining([&] { KittiSequence s(dir2); }, {"times.txt:3", bad, "[0, 1e10)"});
    }
    writeFile(dir2 + "/times.txt", "0.0\n0.2\n0.1\n");
    expectThrowContaining([&] { KittiSequence s(dir2); }, {"times.txt:3", "must increase"});
}

TEST(KittiSequence, poseCountMismatchThrows)
{
    const std::string root = emslam::test::makeTempDir("kitti_poses");
    const std::string dir = writeKittiSequence(root, 4);
    const std::string poses = root + "/poses.txt";
    std::ifstream in(poses);
    std::string l0, l1, l2;
    std::getline(in, l0);
    std::getline(in, l1);
    std::getline(in, l2);
    in.close();
    writeFile(poses, l0 + "\n" + l1 + "\n" + l2 + "\n");
    expectThrowContaining([&] { KittiSequence s(dir, poses); }, {poses, "3 poses", "4 frames"});
    writeFile(poses, l0 + "\n" + l1 + "\n" + l2 + "\n1 0 0 0 0 1 0 0 0 0 1\n");
    expectThrowContaining([&] { KittiSequence s(dir, poses); }, {poses + ":4", "12 numbers"});
    writeFile(poses, l0 + "\n" + l1 + "\n" + l2 + "\n2 0 0 0 0 1 0 0 0 0 1 0\n");
    expectThrowContaining([&] { KittiSequence s(dir, poses); }, {poses + ":4", "rotation"});
    expectThrowContaining([&] { KittiSequence s(dir, root + "/none.txt"); }, {root + "/none.txt"});
}
