// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/CalibrationFiles.h>
#include <emslam/stereo/StereoCalibration.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

using emslam::io::loadEurocCalibration;
using emslam::io::loadKittiCalibration;
using emslam::io::loadStereoCameraFromIniFile;
using emslam::stereo::baselineOf;
using emslam::stereo::loadStereoCameraFromConfig;
using emslam::stereo::validateStereoCamera;

using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

namespace
{
// KITTI sequence 06 numbers, written with CRLF and the extra lines of the full dataset.
const std::string KITTI_P0 =
    "P0: 7.070912000000e+02 0.000000000000e+00 6.018873000000e+02 0.000000000000e+00 "
    "0.000000000000e+00 7.070912000000e+02 1.831104000000e+02 0.000000000000e+00 "
    "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00";
const std::string KITTI_P1 =
    "P1: 7.070912000000e+02 0.000000000000e+00 6.018873000000e+02 -3.798145000000e+02 "
    "0.000000000000e+00 7.070912000000e+02 1.831104000000e+02 0.000000000000e+00 "
    "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00";
const std::string KITTI_P2 =
    "P2: 7.070912e+02 0 6.018873e+02 4.688783e+01 0 7.070912e+02 1.831104e+02 1.178601e-01 0 0 1 "
    "6.203223e-03";
const std::string KITTI_TR =
    "Tr: -1.857739e-03 -9.999659e-01 -8.039975e-03 -4.784944e-03 -6.481465e-03 8.051860e-03 "
    "-9.999466e-01 -7.337429e-02 9.999773e-01 -1.805528e-03 -6.496203e-03 -3.339968e-01";

// A valid EuRoC cam0 sensor.yaml (V1_01 values); tests edit it to break it.
const std::string EUROC_CAM0_YAML = R"(%YAML:1.0
# General sensor definitions.
sensor_type: camera
comment: VI-Sensor cam0 (MT9M034)

# Sensor extrinsics wrt. the body-frame.
T_BS:
  cols: 4
  rows: 4
  data: [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
         0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,
        -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,
         0.0, 0.0, 0.0, 1.0]

# Camera specific definitions.
rate_hz: 20
resolution: [752, 480]
camera_model: pinhole
intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv
distortion_model: radial-tangential
distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
)";

std::string replaced(std::string s, const std::string& from, const std::string& to)
{
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    if (pos != std::string::npos)
    {
        s.replace(pos, from.size(), to);
    }
    return s;
}

/** Writes `cam0_text` as cam0 and the unchanged cam0 text as cam1, then loads them. */
std::function<void()> eurocLoader(const std::string& dir, const std::string& cam0_text)
{
    const std::string f0 = dir + "/cam0.yaml", f1 = dir + "/cam1.yaml";
    writeFile(f0, cam0_text);
    writeFile(f1, EUROC_CAM0_YAML);
    return [f0, f1]() { loadEurocCalibration(f0, f1); };
}

mrpt::img::TStereoCamera distinctStereoCamera()
{
    mrpt::img::TStereoCamera c;
    c.leftCamera.ncols = 800;
    c.leftCamera.nrows = 600;
    c.leftCamera.setIntrinsicParamsFromValues(510.5, 512.25, 401.75, 297.125);
    c.leftCamera.setDistortionPlumbBob(-0.21, 0.043, 0.0012, -0.0007, 0.003);
    c.rightCamera.ncols = 800;
    c.rightCamera.nrows = 600;
    c.rightCamera.setIntrinsicParamsFromValues(505.5, 507.75, 395.5, 301.0);
    c.rightCamera.setDistortionPlumbBob(-0.19, 0.038, -0.0004, 0.0009, 0.0);
    const mrpt::poses::CPose3D T_left_right(0.1215, -0.0021, 0.0033, 0.011, -0.006, 0.004);
    c.rightCameraPose = mrpt::poses::CPose3DQuat(T_left_right).asTPose();
    return c;
}

}  // namespace

// ---------------------------------------------------------------------------
// KITTI
// ---------------------------------------------------------------------------
TEST(CalibrationReaders, kittiRealFileGivesPublishedValues)
{
    EMSLAM_REQUIRE_TEST_DATA(path, "kitti-odometry/sequences/06/calib.txt");
    const auto c = loadKittiCalibration(path, 1226, 370);
    for (const auto* cam : {&c.leftCamera, &c.rightCamera})
    {
        EXPECT_DOUBLE_EQ(cam->fx(), 707.0912);
        EXPECT_DOUBLE_EQ(cam->fy(), 707.0912);
        EXPECT_DOUBLE_EQ(cam->cx(), 601.8873);
        EXPECT_DOUBLE_EQ(cam->cy(), 183.1104);
        EXPECT_EQ(cam->ncols, 1226u);
        EXPECT_EQ(cam->nrows, 370u);
        EXPECT_EQ(cam->distortion, mrpt::img::DistortionModel::none);
    }
    EXPECT_NEAR(c.rightCameraPose.x, 379.8145 / 707.0912, 1e-12);
    EXPECT_NEAR(baselineOf(c), 0.5372, 1e-4);
    EXPECT_EQ(c.rightCameraPose.y, 0.0);
    EXPECT_EQ(c.rightCameraPose.z, 0.0);
    EXPECT_EQ(c.rightCameraPose.qr, 1.0);
}

TEST(CalibrationReaders, kittiSyntheticCrlfWithExtraLines)
{
    const std::string dir = emslam::test::makeTempDir("kitti_crlf");
    const std::string file = dir + "/calib.txt";
    // Right camera first, blank line and the lines a reader must ignore.
    writeFile(
        file, KITTI_P1 + "\r\n\r\n" + KITTI_P2 + "\r\n" + KITTI_P0 + "  \r\n" + KITTI_P2 +
                  "\r\nP3: 1 2 3\r\n" + KITTI_TR + "\r\n");
    const auto c = loadKittiCalibration(file, 1241, 376);
    EXPECT_DOUBLE_EQ(c.leftCamera.fx(), 707.0912);
    EXPECT_DOUBLE_EQ(c.rightCamera.cy(), 183.1104);
    EXPECT_EQ(c.leftCamera.ncols, 1241u);
    EXPECT_EQ(c.rightCamera.nrows, 376u);
    EXPECT_NEAR(baselineOf(c), 0.537150, 1e-6);
    EXPECT_GT(c.rightCameraPose.x, 0.0);
}

TEST(CalibrationReaders, kittiMissingFileThrowsNamingIt)
{
    const std::string file = emslam::test::makeTempDir("kitti_nofile") + "/calib.txt";
    expectThrowContaining([&]() { loadKittiCalibration(file, 1226, 370); }, {file, "not found"});
}

TEST(CalibrationReaders, kittiMissingP1Throws)
{
    const std::string file = emslam::test::makeTempDir("kitti_nop1") + "/calib.txt";
    writeFile(file, KITTI_P0 + "\n" + KITTI_P2 + "\n");
    expectThrowContaining([&]() { loadKittiCalibration(file, 1226, 370); }, {file, "P1"});
}

TEST(CalibrationReaders, kittiGarbledP0Throws)
{
    const std::string dir = emslam::test::makeTempDir("kitti_garbled");
    const std::string file = dir + "/calib.txt";

    // 11 numbers.
    writeFile(file, "P0: 707 0 601 0 0 707 183 0 0 0 1\n" + KITTI_P1 + "\n");
    expectThrowContaining(
        [&]() { loadKittiCalibration(file, 1226, 370); }, {file, "line 1", "11 numbers"});

    // A non-numeric entry.
    writeFile(file, KITTI_P1 + "\nP0: 707 0 601 0 0 7o7 183 0 0 0 1 0\n");
    expectThrowContaining(
        [&]() { loadKittiCalibration(file, 1226, 370); }, {file, "line 2", "'7o7'"});

    // A NaN.
    writeFile(file, "P0: 707 0 601 0 0 707 183 0 0 0 1 nan\n" + KITTI_P1 + "\n");
    expectThrowContaining([&]() { loadKittiCalibration(file, 1226, 370); }, {file, "non-finite"});

    // Zero focal length.
    writeFile(file, "P0: 0 0 601 0 0 707 183 0 0 0 1 0\n" + KITTI_P1 + "\n");
    expectThrowContaining([&]() { loadKittiCalibration(file, 1226, 370); }, {file, "focal"});

    // Zero baseline.
    writeFile(file, KITTI_P0 + "\n" + replaced(KITTI_P1, "-3.798145000000e+02", "0") + "\n");
    expectThrowContaining([&]() { loadKittiCalibration(file, 1226, 370); }, {file, "baseline"});
}

// ---------------------------------------------------------------------------
// EuRoC
// ---------------------------------------------------------------------------
TEST(CalibrationReaders, eurocRealPairMatchesYaml)
{
    EMSLAM_REQUIRE_TEST_DATA(cam0, "euroc-v101-rest/mav0/cam0/sensor.yaml");
    EMSLAM_REQUIRE_TEST_DATA(cam1, "euroc-v101-rest/mav0/cam1/sensor.yaml");
    const auto c = loadEurocCalibration(cam0, cam1);

    EXPECT_EQ(c.leftCamera.ncols, 752u);
    EXPECT_EQ(c.leftCamera.nrows, 480u);
    EXPECT_DOUBLE_EQ(c.leftCamera.fx(), 458.654);
    EXPECT_DOUBLE_EQ(c.leftCamera.fy(), 457.296);
    EXPECT_DOUBLE_EQ(c.leftCamera.cx(), 367.215);
    EXPECT_DOUBLE_EQ(c.leftCamera.cy(), 248.375);
    EXPECT_DOUBLE_EQ(c.rightCamera.fx(), 457.587);
    EXPECT_DOUBLE_EQ(c.rightCamera.fy(), 456.134);
    EXPECT_DOUBLE_EQ(c.rightCamera.cx(), 379.999);
    EXPECT_DOUBLE_EQ(c.rightCamera.cy(), 255.238);
    EXPECT_EQ(c.leftCamera.distortion, mrpt::img::DistortionModel::plumb_bob);
    EXPECT_EQ(c.rightCamera.distortion, mrpt::img::DistortionModel::plumb_bob);
    EXPECT_DOUBLE_EQ(c.leftCamera.k1(), -0.28340811);
    EXPECT_DOUBLE_EQ(c.leftCamera.k2(), 0.07395907);
    EXPECT_DOUBLE_EQ(c.leftCamera.p1(), 0.00019359);
    EXPECT_DOUBLE_EQ(c.leftCamera.p2(), 1.76187114e-05);
    EXPECT_EQ(c.leftCamera.k3(), 0.0);
    EXPECT_DOUBLE_EQ(c.rightCamera.p2(), -3.55590700e-05);

    const double b = baselineOf(c);
    EXPECT_NEAR(b, 0.110, 0.002);
    // The right camera sits on the left camera's +x axis (x right, y down, z forward).
    EXPECT_GT(c.rightCameraPose.x / b, 0.99);

    // Oracle: the right camera's optical centre, mapped to the body frame through
    // the left camera, must land on cam1's T_BS translation.
    const mrpt::poses::CPose3D T_left_right(mrpt::poses::CPose3DQuat(c.rightCameraPose));
    mrpt::math::CMatrixDouble44 m = mrpt::math::CMatrixDouble44::Identity();
    const double r0[12] = {0.0148655429818,  -0.999880929698,  0.00414029679422, -0.0216401454975,
                           0.999557249008,   0.0149672133247,  0.025715529948,   -0.064676986768,
                           -0.0257744366974, 0.00375618835797, 0.999660727178,   0.00981073058949};
    for (int i = 0; i < 12; i++)
    {
        m(i / 4, i % 4) = r0[i];
    }
    const mrpt::poses::CPose3D T_body_left(m);
    const auto right_in_body = (T_body_left + T_left_right).translation();
    EXPECT_NEAR(right_in_body.x, -0.0198435579556, 1e-6);
    EXPECT_NEAR(right_in_body.y, 0.0453689425024, 1e-6);
    EXPECT_NEAR(right_in_body.z, 0.00786212447038, 1e-6);
}

TEST(CalibrationReaders, eurocMissingKeyThrowsNamingIt)
{
    const std::string dir = emslam::test::makeTempDir("euroc_missing");
    for (const std::string key :
         {"intrinsics", "resolution", "distortion_coefficients", "distortion_model"})
    {
        std::string text = EUROC_CAM0_YAML;
        const auto pos = text.find("\n" + key + ":");
        ASSERT_NE(pos, std::string::npos) << key;
        text.erase(pos + 1, text.find('\n', pos + 1) - pos);
        expectThrowContaining(eurocLoader(dir, text), {dir + "/cam0.yaml", "'" + key + "'"});
    }
    // T_BS's data list spans several lines: drop the whole block.
    const auto begin = EUROC_CAM0_YAML.find("T_BS:");
    const auto end = EUROC_CAM0_YAML.find("# Camera specific");
    std::string no_tbs = EUROC_CAM0_YAML;
    no_tbs.erase(begin, end - begin);
    expectThrowContaining(eurocLoader(dir, no_tbs), {"cam0.yaml", "'T_BS'"});

    expectThrowContaining(
        [&]() { loadEurocCalibration(dir + "/none.yaml", dir + "/cam1.yaml"); },
        {dir + "/none.yaml", "not found"});
}

TEST(CalibrationReaders, eurocMalformedThrows)
{
    const std::string dir = emslam::test::makeTempDir("euroc_malformed");
    const std::string intr = "[458.654, 457.296, 367.215, 248.375]";
    expectThrowContaining(
        eurocLoader(dir, replaced(EUROC_CAM0_YAML, intr, "[458.654, abc, 367.215, 248.375]")),
        {"cam0.yaml", "'intrinsics'", "not a number"});
    expectThrowContaining(
        eurocLoader(dir, replaced(EUROC_CAM0_YAML, intr, "[458.654, 457.296, 367.215]")),
        {"cam0.yaml", "'intrinsics'", "3 numbers"});
    expectThrowContaining(
        eurocLoader(dir, replaced(EUROC_CAM0_YAML, intr, "[458.654, 457.296, 367.215, 248.375")),
        {"cam0.yaml", "malformed"});
    expectThrowContaining(
        eurocLoader(dir, replaced(EUROC_CAM0_YAML, intr, "[0, 457.296, 367.215, 248.375]")),
        {"cam0.yaml", "focal"});
    expectThrowContaining(
        eurocLoader(dir, replaced(EUROC_CAM0_YAML, "radial-tangential", "equidistant")),
        {"cam0.yaml", "equidistant"});
    expectThrowContaining(
        eurocLoader(dir, replaced(EUROC_CAM0_YAML, "0.0, 0.0, 0.0, 1.0]", "0.0, 0.0, 1.0]")),
        {"cam0.yaml", "'T_BS.data'", "15 numbers"});
    // Identical cam0/cam1 files: both cameras at the same place.
    expectThrowContaining(eurocLoader(dir, EUROC_CAM0_YAML), {"cam0.yaml", "zero baseline"});
}

// ---------------------------------------------------------------------------
// MRPT INI form
// ---------------------------------------------------------------------------
TEST(CalibrationReaders, iniRoundTripThroughText)
{
    const auto orig = distinctStereoCamera();
    mrpt::config::CConfigFileMemory c;
    orig.saveToConfigFile("CALIB", c);
    // Re-parse the text: reading back from `c` itself would return defaults.
    const mrpt::config::CConfigFileMemory reparsed(c.getContent());
    const auto loaded = loadStereoCameraFromConfig(reparsed, "CALIB");

    for (const auto& [a, b] :
         {std::pair{&orig.leftCamera, &loaded.leftCamera},
          std::pair{&orig.rightCamera, &loaded.rightCamera}})
    {
        EXPECT_EQ(a->ncols, b->ncols);
        EXPECT_EQ(a->nrows, b->nrows);
        EXPECT_NEAR(a->fx(), b->fx(), 5e-6);
        EXPECT_NEAR(a->fy(), b->fy(), 5e-6);
        EXPECT_NEAR(a->cx(), b->cx(), 5e-6);
        EXPECT_NEAR(a->cy(), b->cy(), 5e-6);
        EXPECT_EQ(a->distortion, b->distortion);
        for (std::size_t i = 0; i < a->dist.size(); i++)
        {
            EXPECT_NEAR(a->dist[i], b->dist[i], 1e-8) << "dist[" << i << "]";
        }
    }
    // MRPT 2.5.8 writes pose_quaternion with 6 decimals (and fx.. with 5, dist
    // with 7 significant digits): the round trip is exact only to that precision.
    const auto& p = orig.rightCameraPose;
    const auto& q = loaded.rightCameraPose;
    for (const auto& [a, b] :
         {std::pair{p.x, q.x}, std::pair{p.y, q.y}, std::pair{p.z, q.z}, std::pair{p.qr, q.qr},
          std::pair{p.qx, q.qx}, std::pair{p.qy, q.qy}, std::pair{p.qz, q.qz}})
    {
        EXPECT_NEAR(a, b, 1e-6);
    }
    // The loader re-normalises the rounded quaternion.
    EXPECT_NEAR(q.qr * q.qr + q.qx * q.qx + q.qy * q.qy + q.qz * q.qz, 1.0, 1e-12);
    EXPECT_NEAR(baselineOf(loaded), baselineOf(orig), 1e-6);

    // Same text through a file.
    const std::string file = emslam::test::makeTempDir("ini_roundtrip") + "/calib.ini";
    writeFile(file, c.getContent());
    EXPECT_NEAR(baselineOf(loadStereoCameraFromIniFile(file, "CALIB")), baselineOf(orig), 1e-6);
}

TEST(CalibrationReaders, iniMissingSectionThrows)
{
    mrpt::config::CConfigFileMemory c;
    distinctStereoCamera().saveToConfigFile("CALIB", c);
    const mrpt::config::CConfigFileMemory reparsed(c.getContent());
    expectThrowContaining(
        [&]() { loadStereoCameraFromConfig(reparsed, "OTHER"); }, {"OTHER", "missing section"});

    // Drop only the pose section.
    const std::string text = c.getContent();
    const auto pos = text.find("[CALIB_LEFT2RIGHT_POSE]");
    ASSERT_NE(pos, std::string::npos);
    const mrpt::config::CConfigFileMemory no_pose(text.substr(0, pos));
    expectThrowContaining(
        [&]() { loadStereoCameraFromConfig(no_pose, "CALIB"); }, {"CALIB_LEFT2RIGHT_POSE"});

    const std::string missing = emslam::test::makeTempDir("ini_missing") + "/none.ini";
    expectThrowContaining(
        [&]() { loadStereoCameraFromIniFile(missing, "CALIB"); }, {missing, "not found"});
}

TEST(CalibrationReaders, iniInvalidValuesThrow)
{
    mrpt::config::CConfigFileMemory c;
    auto cam = distinctStereoCamera();
    cam.rightCamera.fx(-5.0);
    cam.saveToConfigFile("CALIB", c);
    const mrpt::config::CConfigFileMemory reparsed(c.getContent());
    expectThrowContaining(
        [&]() { loadStereoCameraFromConfig(reparsed, "CALIB"); }, {"CALIB", "right", "focal"});
}

// ---------------------------------------------------------------------------
// validateStereoCamera / baselineOf
// ---------------------------------------------------------------------------
TEST(CalibrationReaders, validateRejectsUnusableCalibrations)
{
    EXPECT_NO_THROW(validateStereoCamera(distinctStereoCamera(), "ok"));

    auto zero_focal = distinctStereoCamera();
    zero_focal.leftCamera.fy(0.0);
    expectThrowContaining(
        [&]() { validateStereoCamera(zero_focal, "thing-A"); }, {"thing-A", "left", "focal"});

    auto zero_size = distinctStereoCamera();
    zero_size.rightCamera.ncols = 0;
    expectThrowContaining(
        [&]() { validateStereoCamera(zero_size, "thing-B"); }, {"thing-B", "size"});

    auto nan_cx = distinctStereoCamera();
    nan_cx.leftCamera.cx(std::numeric_limits<double>::quiet_NaN());
    expectThrowContaining([&]() { validateStereoCamera(nan_cx, "thing-C"); }, {"thing-C", "NaN"});

    auto nan_pose = distinctStereoCamera();
    nan_pose.rightCameraPose.y = std::numeric_limits<double>::quiet_NaN();
    expectThrowContaining([&]() { validateStereoCamera(nan_pose, "thing-D"); }, {"thing-D", "NaN"});

    auto no_baseline = distinctStereoCamera();
    no_baseline.rightCameraPose.x = no_baseline.rightCameraPose.y = no_baseline.rightCameraPose.z =
        0.0;
    expectThrowContaining(
        [&]() { validateStereoCamera(no_baseline, "thing-E"); }, {"thing-E", "zero baseline"});
}

TEST(CalibrationReaders, baselineIsNormOfRightCameraPosition)
{
    auto c = distinctStereoCamera();
    c.rightCameraPose.x = 0.3;
    c.rightCameraPose.y = -0.4;
    c.rightCameraPose.z = 1.2;
    EXPECT_DOUBLE_EQ(baselineOf(c), 1.3);
}
