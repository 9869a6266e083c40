// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/OpenCvStereoCalibration.h>
#include <emslam/stereo/StereoCalibration.h>

#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <string>

using emslam::io::loadOpenCvStereoCalibration;
using emslam::io::saveOpenCvStereoCalibration;
using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

namespace
{
/** A raw pair: different intrinsics, distortion, a small rotation, 12 cm baseline. */
mrpt::img::TStereoCamera rawPair()
{
    mrpt::img::TStereoCamera cam;
    cam.leftCamera.ncols = cam.rightCamera.ncols = 640;
    cam.leftCamera.nrows = cam.rightCamera.nrows = 480;
    cam.leftCamera.setIntrinsicParamsFromValues(401, 402, 319.5, 241.25);
    cam.rightCamera.setIntrinsicParamsFromValues(399, 398.5, 322, 238);
    cam.leftCamera.distortion = cam.rightCamera.distortion = mrpt::img::DistortionModel::plumb_bob;
    cam.leftCamera.dist = {-0.21, 0.05, 0.001, -0.0005, 0.002, 0, 0, 0};
    cam.rightCamera.dist = {-0.2, 0.04, -0.001, 0.0002, 0, 0, 0, 0};
    cam.rightCameraPose =
        mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(0.12, 0.003, -0.002, 0.01, -0.02, 0.005))
            .asTPose();
    return cam;
}

void expectSamePair(const mrpt::img::TStereoCamera& a, const mrpt::img::TStereoCamera& b)
{
    for (const auto& [ca, cb] :
         {std::pair{&a.leftCamera, &b.leftCamera}, std::pair{&a.rightCamera, &b.rightCamera}})
    {
        EXPECT_EQ(ca->ncols, cb->ncols);
        EXPECT_EQ(ca->nrows, cb->nrows);
        EXPECT_NEAR(ca->fx(), cb->fx(), 1e-12);
        EXPECT_NEAR(ca->fy(), cb->fy(), 1e-12);
        EXPECT_NEAR(ca->cx(), cb->cx(), 1e-12);
        EXPECT_NEAR(ca->cy(), cb->cy(), 1e-12);
        EXPECT_EQ(ca->distortion, cb->distortion);
        for (std::size_t i = 0; i < 8; ++i)
        {
            EXPECT_NEAR(ca->dist[i], cb->dist[i], 1e-15) << i;
        }
    }
    const mrpt::poses::CPose3D pa(mrpt::poses::CPose3DQuat(a.rightCameraPose));
    const mrpt::poses::CPose3D pb(mrpt::poses::CPose3DQuat(b.rightCameraPose));
    EXPECT_LT(emslam::test::maxPoseDifference(pa, pb), 1e-12);
}

const char* const K_LINES =
    "M1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 400, 0, 320, 0, 400, "
    "240, 0, 0, 1 ]\nM2: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 400, 0, "
    "320, 0, 400, 240, 0, 0, 1 ]\n";
}  // namespace

TEST(OpenCvStereoCalibration, roundTripsThroughYamlXmlAndJson)
{
    const std::string dir = emslam::test::makeTempDir("ocv_calib_rt");
    const auto cam = rawPair();
    for (const char* ext : {".yml", ".xml", ".json"})
    {
        const std::string f = dir + "/c" + ext;
        saveOpenCvStereoCalibration(f, cam);
        SCOPED_TRACE(f);
        expectSamePair(loadOpenCvStereoCalibration(f), cam);
    }
}

// OpenCV's convention: X_right = R X_left + T; the right camera of a
// standard rig sits at +x of the left one, so T = (-b, 0, 0).
TEST(OpenCvStereoCalibration, followsOpenCvsExtrinsicConvention)
{
    const std::string dir = emslam::test::makeTempDir("ocv_calib_conv");
    const auto cam = rawPair();
    saveOpenCvStereoCalibration(dir + "/c.yml", cam);
    cv::FileStorage fs(dir + "/c.yml", cv::FileStorage::READ);
    cv::Mat R, T;
    fs["R"] >> R;
    fs["T"] >> T;
    // A point in the left frame, mapped into the right one both ways.
    const mrpt::poses::CPose3D T_left_right(mrpt::poses::CPose3DQuat(cam.rightCameraPose));
    const mrpt::math::TPoint3D p_left(0.3, -0.2, 4.0);
    const auto p_right = T_left_right.inverseComposePoint(p_left);
    const cv::Mat x = R * (cv::Mat_<double>(3, 1) << p_left.x, p_left.y, p_left.z) + T;
    EXPECT_NEAR(x.at<double>(0), p_right.x, 1e-12);
    EXPECT_NEAR(x.at<double>(1), p_right.y, 1e-12);
    EXPECT_NEAR(x.at<double>(2), p_right.z, 1e-12);
    EXPECT_LT(T.at<double>(0), -0.11);
}

// The stereo_calib sample's layout: intrinsics.yml (M, D) and extrinsics.yml
// (R, T in the pattern's unit), K aliases, a Rodrigues R, no image size.
TEST(OpenCvStereoCalibration, readsTwoFilesAliasesRodriguesAndScale)
{
    const std::string dir = emslam::test::makeTempDir("ocv_calib_two");
    writeFile(
        dir + "/intrinsics.yml",
        "%YAML:1.0\nK1: [400, 0, 320, 0, 400, 240, 0, 0, 1]\nD1: [-0.1, 0.01, 0, 0]\n"
        "K2: [410, 0, 321, 0, 409, 239, 0, 0, 1]\nD2: []\n");
    const cv::Mat rvec = (cv::Mat_<double>(3, 1) << 0.0, 0.02, 0.0);
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    writeFile(dir + "/extrinsics.yml", "%YAML:1.0\nR: [0, 0.02, 0]\nT: [-100, 0, 0]\n");
    const auto cam =
        loadOpenCvStereoCalibration(dir + "/intrinsics.yml", dir + "/extrinsics.yml", 0.001);
    EXPECT_EQ(cam.leftCamera.ncols, 0U);  // no size in the files
    EXPECT_EQ(cam.rightCamera.fx(), 410.0);
    EXPECT_EQ(cam.leftCamera.distortion, mrpt::img::DistortionModel::plumb_bob);
    EXPECT_EQ(cam.leftCamera.dist[0], -0.1);
    EXPECT_EQ(cam.rightCamera.distortion, mrpt::img::DistortionModel::none);
    // Position -R^T T in metres.
    const cv::Mat c = -R.t() * (cv::Mat_<double>(3, 1) << -0.1, 0, 0);
    EXPECT_NEAR(cam.rightCameraPose.x, c.at<double>(0), 1e-12);
    EXPECT_NEAR(cam.rightCameraPose.z, c.at<double>(2), 1e-12);
    EXPECT_NEAR(emslam::stereo::baselineOf(cam), 0.1, 1e-12);
}

TEST(OpenCvStereoCalibration, badFilesThrowNamingFileAndKey)
{
    const std::string dir = emslam::test::makeTempDir("ocv_calib_bad");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/none.yml"); }, {"none.yml", "file not found"});
    writeFile(dir + "/noR.yml", std::string("%YAML:1.0\n") + K_LINES + "T: [-0.1, 0, 0]\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/noR.yml"); }, {"noR.yml", "missing key R"});
    writeFile(
        dir + "/badR.yml",
        std::string("%YAML:1.0\n") + K_LINES + "R: [1, 0, 0, 0, 2, 0, 0, 0, 1]\nT: [-0.1, 0, 0]\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/badR.yml"); }, {"badR.yml", "not a rotation"});
    writeFile(
        dir + "/badT.yml", std::string("%YAML:1.0\n") + K_LINES + "R: [0, 0, 0]\nT: [-0.1, 0]\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/badT.yml"); },
        {"badT.yml", "T has 2 numbers, expected 3"});
    writeFile(
        dir + "/badD.yml", std::string("%YAML:1.0\n") + K_LINES +
                               "D1: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]\nR: [0, 0, 0]\nT: "
                               "[-0.1, 0, 0]\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/badD.yml"); }, {"D1 has 12 numbers"});
    writeFile(
        dir + "/skew.yml",
        "%YAML:1.0\nM1: [400, 3, 320, 0, 400, 240, 0, 0, 1]\nM2: [400, 0, 320, 0, 400, 240, 0, 0, "
        "1]\nR: [0, 0, 0]\nT: [-0.1, 0, 0]\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/skew.yml"); }, {"M1/K1", "skew"});
    writeFile(
        dir + "/nan.yml", std::string("%YAML:1.0\n") + K_LINES + "R: [0, 0, 0]\nT: [.nan, 0, 0]\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/nan.yml"); }, {"nan.yml", "T", "non-finite"});
    writeFile(
        dir + "/size.yml",
        std::string("%YAML:1.0\n") + K_LINES + "R: [0, 0, 0]\nT: [-0.1, 0, 0]\nimage_width: 640\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/size.yml"); }, {"image_width and image_height"});
    // A matrix header asking for 10^10 elements (cv::Mat's reader would
    // allocate them before reading the one value; found by the fuzzer).
    writeFile(
        dir + "/huge.yml",
        "%YAML:1.0\nM1: !!opencv-matrix\n   rows: 100000\n   cols: 100000\n   dt: d\n   "
        "data: [ 1. ]\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/huge.yml"); },
        {"huge.yml", "M1/K1", "100000x100000 matrix is not a calibration"});
    writeFile(
        dir + "/short.yml",
        "%YAML:1.0\nM1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 2. ]\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/short.yml"); },
        {"M1/K1", "2 data values for a 3x3 matrix"});
    // What OpenCV's parser must never see: deep nesting, binary data, a huge file.
    writeFile(dir + "/deep.yml", "%YAML:1.0\nR: " + std::string(5000, '[') + "\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/deep.yml"); }, {"deep.yml", "nested too deeply"});
    writeFile(dir + "/nul.yml", std::string("%YAML:1.0\nR: \0\n", 14));
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/nul.yml"); }, {"nul.yml", "NUL"});
    writeFile(dir + "/big.yml", "%YAML:1.0\n# " + std::string(70000, 'x') + "\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/big.yml"); }, {"big.yml", "larger than"});
    writeFile(dir + "/garbage.yml", "%YAML:1.0\nM1: [1, 2\n  : ] ]\n");
    expectThrowContaining(
        [&] { loadOpenCvStereoCalibration(dir + "/garbage.yml"); }, {"garbage.yml"});
    const std::string ok = dir + "/ok.yml";
    saveOpenCvStereoCalibration(ok, rawPair());
    expectThrowContaining([&] { loadOpenCvStereoCalibration(ok, "", 0.0); }, {"translation scale"});
}

TEST(OpenCvStereoCalibration, recognisesStorageExtensions)
{
    EXPECT_TRUE(emslam::io::isOpenCvStorageFile("a/b.yml"));
    EXPECT_TRUE(emslam::io::isOpenCvStorageFile("B.YAML"));
    EXPECT_TRUE(emslam::io::isOpenCvStorageFile("c.xml"));
    EXPECT_TRUE(emslam::io::isOpenCvStorageFile("c.json"));
    EXPECT_FALSE(emslam::io::isOpenCvStorageFile("c.ini"));
    EXPECT_FALSE(emslam::io::isOpenCvStorageFile("yml"));
}
