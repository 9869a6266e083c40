// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/hwdrivers/CDigiclopsStereoCamera.h>
#include <emslam/hwdrivers/DeviceList.h>
#include <emslam/stereo/StereoRectifier.h>

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/random/RandomGenerators.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using emslam::hwdrivers::CDigiclopsStereoCamera;
using emslam::hwdrivers::PackedFrameFormat;
using emslam::hwdrivers::PackedLayout;

namespace
{
const char* CALIB_64x48 = R"(
[CAL_LEFT]
resolution = [64 48]
cx = 31.5
cy = 23.5
fx = 50
fy = 50
distortion_model = none
dist = []
[CAL_RIGHT]
resolution = [64 48]
cx = 31.5
cy = 23.5
fx = 50
fy = 50
distortion_model = none
dist = []
[CAL_LEFT2RIGHT_POSE]
pose_quaternion = [0.1 0 0 1 0 0 0]
[CAL_THIRD]
resolution = [64 48]
cx = 30
cy = 22
fx = 52
fy = 51
distortion_model = plumb_bob
dist = [0.01 -0.002 0 0 0]
[CAL_LEFT2THIRD_POSE]
pose_quaternion = [0 -0.1 0.002 1 0 0 0]
)";

/** Every key with a value different from its default. */
std::string fixtureIni(const std::string& extra_sensor_keys = "")
{
    return std::string(R"(
[CAM]
driver = CDigiclopsStereoCamera
sensorLabel = TRINO
process_rate = 14
camera_guid = 00b09d01004a1b2c
camera_index = 2
video_mode = FORMAT7_3
framerate = 14
iso_speed = 800
shutter = 120
gain = 30
exposure = 200
dma_buffers = 4
pixel_layout = rgb24
planar_channels = 2
channel_left = 2
channel_right = 1
channel_third = 0
calibration_section = CAL
rectify = false
rectify_alpha = 0.25
pose_x = 0.1
pose_y = 0.2
pose_z = 1.3
pose_yaw_deg = 10
pose_pitch_deg = -5
pose_roll_deg = 2
compute_range_scan = true
stereo_section = MyStereo
)") + extra_sensor_keys +
           CALIB_64x48 + R"(
[MyStereo]
num_disparities = 32
block_size = 7
)";
}

CDigiclopsStereoCamera::TParameters loadParams(const std::string& ini)
{
    mrpt::config::CConfigFileMemory c(ini);
    CDigiclopsStereoCamera::TParameters p;
    p.loadFromConfigFile(c, "CAM");
    return p;
}

std::uint8_t pat(int ch, int r, int c)
{
    return static_cast<std::uint8_t>((r * 5 + c * 11 + ch * 77) & 0xFF);
}

/** A packed rgb24 frame whose channel k holds pat(k, ...). */
std::vector<std::uint8_t> patternFrame(const PackedFrameFormat& f)
{
    std::vector<cv::Mat> imgs;
    for (unsigned int k = 0; k < f.channels(); ++k)
    {
        cv::Mat m(static_cast<int>(f.height), static_cast<int>(f.width), CV_8UC1);
        for (int r = 0; r < m.rows; ++r)
        {
            for (int c = 0; c < m.cols; ++c)
            {
                m.at<std::uint8_t>(r, c) = pat(static_cast<int>(k), r, c);
            }
        }
        imgs.push_back(m);
    }
    return emslam::hwdrivers::interleave(imgs, f);
}

bool equalsPattern(const mrpt::img::CImage& im, int ch)
{
    const cv::Mat& m = im.asCvMatRef();
    if (m.type() != CV_8UC1)
    {
        return false;
    }
    for (int r = 0; r < m.rows; ++r)
    {
        for (int c = 0; c < m.cols; ++c)
        {
            if (m.at<std::uint8_t>(r, c) != pat(ch, r, c))
            {
                return false;
            }
        }
    }
    return true;
}
}  // namespace

TEST(CDigiclopsStereoCamera, loadsEveryKeyAndTheCalibration)
{
    const auto p = loadParams(fixtureIni());
    EXPECT_EQ(p.camera_guid, 0x00b09d01004a1b2cULL);
    EXPECT_EQ(p.camera_index, 2);
    EXPECT_EQ(p.video_mode, "FORMAT7_3");
    EXPECT_EQ(p.framerate, 14.0);
    EXPECT_EQ(p.iso_speed, 800);
    EXPECT_EQ(p.shutter, 120);
    EXPECT_EQ(p.gain, 30);
    EXPECT_EQ(p.exposure, 200);
    EXPECT_EQ(p.dma_buffers, 4);
    EXPECT_EQ(p.pixel_layout, "rgb24");
    EXPECT_EQ(p.planar_channels, 2);
    EXPECT_EQ(p.channel_left, 2);
    EXPECT_EQ(p.channel_right, 1);
    EXPECT_EQ(p.channel_third, 0);
    EXPECT_EQ(p.calibration_section, "CAL");
    EXPECT_FALSE(p.rectify);
    EXPECT_EQ(p.rectify_alpha, 0.25);
    EXPECT_EQ(p.pose_z, 1.3);
    EXPECT_EQ(p.pose_yaw_deg, 10.0);
    EXPECT_EQ(p.pose_pitch_deg, -5.0);
    EXPECT_EQ(p.pose_roll_deg, 2.0);
    EXPECT_TRUE(p.compute_range_scan);
    EXPECT_EQ(p.stereo_section, "MyStereo");
    EXPECT_EQ(p.stereo.num_disparities, 32);
    EXPECT_EQ(p.stereo.block_size, 7);
    EXPECT_EQ(p.stereo_camera.leftCamera.ncols, 64U);
    EXPECT_EQ(p.stereo_camera.rightCamera.fx(), 50.0);
    EXPECT_NEAR(p.stereo_camera.rightCameraPose.x, 0.1, 1e-12);
    EXPECT_EQ(p.third_camera.fx(), 52.0);
    EXPECT_EQ(p.third_camera.dist[0], 0.01);
    EXPECT_NEAR(p.T_left_third.y(), -0.1, 1e-12);
    EXPECT_NEAR(p.T_left_third.z(), 0.002, 1e-12);
    const auto f = p.frameFormat();
    EXPECT_EQ(f.channels(), 3U);
    EXPECT_EQ(f.bytesPerFrame(), 3U * 64U * 48U);
}

TEST(CDigiclopsStereoCamera, saveReparseLoadRoundTrips)
{
    const auto p = loadParams(fixtureIni());
    mrpt::config::CConfigFileMemory out;
    p.saveToConfigFile(out, "CAM");
    const mrpt::config::CConfigFileMemory reparsed(out.getContent());
    CDigiclopsStereoCamera::TParameters q;
    q.loadFromConfigFile(reparsed, "CAM");
    EXPECT_EQ(q.camera_guid, p.camera_guid);
    EXPECT_EQ(q.camera_index, p.camera_index);
    EXPECT_EQ(q.video_mode, p.video_mode);
    EXPECT_EQ(q.framerate, p.framerate);
    EXPECT_EQ(q.iso_speed, p.iso_speed);
    EXPECT_EQ(q.shutter, p.shutter);
    EXPECT_EQ(q.gain, p.gain);
    EXPECT_EQ(q.exposure, p.exposure);
    EXPECT_EQ(q.dma_buffers, p.dma_buffers);
    EXPECT_EQ(q.pixel_layout, p.pixel_layout);
    EXPECT_EQ(q.planar_channels, p.planar_channels);
    EXPECT_EQ(q.channel_left, p.channel_left);
    EXPECT_EQ(q.channel_right, p.channel_right);
    EXPECT_EQ(q.channel_third, p.channel_third);
    EXPECT_EQ(q.calibration_section, p.calibration_section);
    EXPECT_EQ(q.rectify, p.rectify);
    EXPECT_EQ(q.rectify_alpha, p.rectify_alpha);
    EXPECT_EQ(q.pose_x, p.pose_x);
    EXPECT_EQ(q.pose_y, p.pose_y);
    EXPECT_EQ(q.pose_z, p.pose_z);
    EXPECT_EQ(q.pose_yaw_deg, p.pose_yaw_deg);
    EXPECT_EQ(q.pose_pitch_deg, p.pose_pitch_deg);
    EXPECT_EQ(q.pose_roll_deg, p.pose_roll_deg);
    EXPECT_EQ(q.compute_range_scan, p.compute_range_scan);
    EXPECT_EQ(q.stereo_section, p.stereo_section);
    EXPECT_EQ(q.stereo.num_disparities, p.stereo.num_disparities);
    EXPECT_EQ(q.stereo.block_size, p.stereo.block_size);
    // Calibration (acceptance 1: it round-trips through the INI).
    EXPECT_TRUE(q.stereo_camera.leftCamera == p.stereo_camera.leftCamera);
    EXPECT_TRUE(q.stereo_camera.rightCamera == p.stereo_camera.rightCamera);
    EXPECT_NEAR(q.stereo_camera.rightCameraPose.x, p.stereo_camera.rightCameraPose.x, 1e-12);
    EXPECT_NEAR(q.stereo_camera.rightCameraPose.qr, p.stereo_camera.rightCameraPose.qr, 1e-12);
    EXPECT_TRUE(q.third_camera == p.third_camera);
    for (int i = 0; i < 3; ++i)
    {
        EXPECT_NEAR(q.T_left_third.m_coords[i], p.T_left_third.m_coords[i], 1e-12);
    }
    EXPECT_NEAR((q.T_left_third - p.T_left_third).norm(), 0.0, 1e-12);
}

TEST(CDigiclopsStereoCamera, invalidValuesThrowNamingTheKey)
{
    using emslam::test::expectThrowContaining;
    auto with = [](const std::string& keys)
    {
        // Later keys override the fixture's values of the same name.
        std::string ini = fixtureIni();
        const auto pos = ini.find("[CAL_LEFT]");
        ini.insert(pos, keys + "\n");
        return ini;
    };
    expectThrowContaining([&] { loadParams(with("iso_speed = 300")); }, {"iso_speed", "300"});
    expectThrowContaining([&] { loadParams(with("channel_left = 3")); }, {"channel_left", "0..2"});
    expectThrowContaining([&] { loadParams(with("channel_left = 1")); }, {"channel_right"});
    expectThrowContaining([&] { loadParams(with("pixel_layout = yuv")); }, {"yuv", "rgb24"});
    expectThrowContaining([&] { loadParams(with("camera_guid = xyz")); }, {"camera_guid", "xyz"});
    expectThrowContaining([&] { loadParams(with("rectify_alpha = 2")); }, {"rectify_alpha"});
    expectThrowContaining([&] { loadParams(with("framerate = 0")); }, {"framerate"});
    expectThrowContaining([&] { loadParams(with("calibration_section = NOPE")); }, {"NOPE"});
    // A 3-image layout needs the third camera.
    std::string no_third = fixtureIni();
    no_third.replace(no_third.find("[CAL_THIRD]"), 11, "[CAL_OTHER]");
    expectThrowContaining([&] { loadParams(no_third); }, {"CAL_THIRD"});
    // ... a 2-image layout does not.
    EXPECT_NO_THROW(loadParams(
        [&]
        {
            std::string s = no_third;
            s.insert(
                s.find("[CAL_LEFT]"),
                "pixel_layout = interleaved16\nchannel_left = 1\n"
                "channel_right = 0\n");
            return s;
        }()));
}

TEST(CDigiclopsStereoCamera, createdByNameAndLoadedLikeAnyMrptSensor)
{
    auto s = mrpt::hwdrivers::CGenericSensor::createSensorPtr("CDigiclopsStereoCamera");
    ASSERT_TRUE(s);
    const mrpt::config::CConfigFileMemory c(fixtureIni());
    s->loadConfig(c, "CAM");
    EXPECT_EQ(s->getSensorLabel(), "TRINO");
    EXPECT_EQ(s->getProcessRate(), 14.0);
    auto* d = dynamic_cast<CDigiclopsStereoCamera*>(s.get());
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(d->parameters().camera_guid, 0x00b09d01004a1b2cULL);
}

TEST(CDigiclopsStereoCamera, shippedConfigLoads)
{
    const mrpt::config::CConfigFile c(emslam::test::sourceDir() + "/config/grabber/digiclops.ini");
    CDigiclopsStereoCamera cam;
    ASSERT_NO_THROW(cam.loadConfig(c, "DIGICLOPS"));
    EXPECT_EQ(cam.parameters().stereo_camera.leftCamera.ncols, 640U);
    EXPECT_EQ(cam.parameters().frameFormat().bytesPerFrame(), 640U * 480U * 3U);
    EXPECT_NEAR(cam.parameters().stereo_camera.rightCameraPose.x, 0.10, 1e-12);
}

TEST(CDigiclopsStereoCamera, initializeWithoutCameraNamesTheCause)
{
    if (!emslam::hwdrivers::listDevices().iidc_cameras.empty())
    {
        GTEST_SKIP() << "an IIDC camera is attached";
    }
    CDigiclopsStereoCamera cam;
    const mrpt::config::CConfigFileMemory c(fixtureIni());
    cam.loadConfig(c, "CAM");
    emslam::test::expectThrowContaining(
        [&] { cam.initialize(); }, {"no device", "IEEE-1394", "USB", "--list-devices"});
    EXPECT_EQ(cam.getState(), mrpt::hwdrivers::CGenericSensor::ssError);
    EXPECT_THROW(cam.doProcess(), std::logic_error);
}

TEST(CDigiclopsStereoCamera, convertFrameDeinterleavesIntoLabelledObservations)
{
    auto p = loadParams(fixtureIni());
    p.compute_range_scan = false;
    p.rectify = false;
    CDigiclopsStereoCamera cam;
    cam.setSensorLabel("TRINO");
    cam.setParameters(p);
    const auto frame = patternFrame(p.frameFormat());
    const auto t = mrpt::Clock::fromDouble(1700000000.25);
    const auto objs = cam.convertFrame(frame.data(), frame.size(), t);
    ASSERT_EQ(objs.size(), 2U);
    const auto st = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(objs[0]);
    const auto im = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(objs[1]);
    ASSERT_TRUE(st);
    ASSERT_TRUE(im);
    EXPECT_EQ(st->timestamp, t);
    EXPECT_EQ(im->timestamp, t);
    EXPECT_EQ(st->sensorLabel, "TRINO");
    EXPECT_EQ(im->sensorLabel, "TRINO_THIRD");
    EXPECT_TRUE(st->hasImageRight);
    // channel_left = 2, channel_right = 1, channel_third = 0 in the fixture.
    EXPECT_TRUE(equalsPattern(st->imageLeft, 2));
    EXPECT_TRUE(equalsPattern(st->imageRight, 1));
    EXPECT_TRUE(equalsPattern(im->image, 0));
    EXPECT_EQ(st->leftCamera.fx(), 50.0);
    EXPECT_NEAR(st->rightCameraPose.x(), 0.1, 1e-12);
    EXPECT_NEAR(st->cameraPose.z(), 1.3, 1e-12);
    // Third camera pose = left pose + LEFT2THIRD; raw intrinsics kept (no rectification).
    const auto expected_third = mrpt::poses::CPose3D(st->cameraPose) + p.T_left_third;
    EXPECT_NEAR((im->cameraPose - expected_third).norm(), 0.0, 1e-9);
    EXPECT_EQ(im->cameraParams.fx(), 52.0);
    EXPECT_EQ(im->cameraParams.dist[0], 0.01);

    // A frame of the wrong size is rejected with both sizes.
    emslam::test::expectThrowContaining(
        [&] { cam.convertFrame(frame.data(), frame.size() - 3, t); }, {"9213", "9216"});
}

TEST(CDigiclopsStereoCamera, twoCameraLayoutEmitsOnlyThePair)
{
    auto p = loadParams(fixtureIni());
    p.pixel_layout = "interleaved16";
    p.channel_left = 1;
    p.channel_right = 0;
    p.compute_range_scan = false;
    CDigiclopsStereoCamera cam;
    cam.setParameters(p);
    const auto frame = patternFrame(p.frameFormat());
    ASSERT_EQ(frame.size(), 2U * 64U * 48U);
    const auto objs = cam.convertFrame(frame.data(), frame.size(), mrpt::Clock::now());
    ASSERT_EQ(objs.size(), 1U);
    const auto st = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(objs[0]);
    ASSERT_TRUE(st);
    EXPECT_TRUE(equalsPattern(st->imageLeft, 1));
    EXPECT_TRUE(equalsPattern(st->imageRight, 0));
}

TEST(CDigiclopsStereoCamera, rectifiesAndUndistortsWithTheIniCalibration)
{
    // Right camera slightly rotated and the third camera distorted: both get corrected.
    std::string ini = fixtureIni();
    ini.replace(
        ini.find("pose_quaternion = [0.1 0 0 1 0 0 0]"), 34,
        "pose_quaternion = [0.1 0 0 0.99996 0 0.0087 0]");
    auto p = loadParams(ini);
    p.compute_range_scan = false;
    p.rectify = true;
    CDigiclopsStereoCamera cam;
    cam.setParameters(p);
    const auto frame = patternFrame(p.frameFormat());
    const auto objs = cam.convertFrame(frame.data(), frame.size(), mrpt::Clock::now());
    ASSERT_EQ(objs.size(), 2U);
    const auto st = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(objs[0]);
    const auto im = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(objs[1]);
    mrpt::img::TStereoCamera out_cal;
    st->getStereoCameraParams(out_cal);
    EXPECT_TRUE(emslam::stereo::StereoRectifier::isAlreadyRectified(out_cal));
    EXPECT_FALSE(equalsPattern(st->imageRight, 1));
    EXPECT_EQ(im->cameraParams.distortion, mrpt::img::DistortionModel::none);
    EXPECT_FALSE(equalsPattern(im->image, 0));
}

TEST(CDigiclopsStereoCamera, computesTheRangeScanOnline)
{
    auto p = loadParams(fixtureIni());
    p.rectify = false;
    p.stereo.min_range = 0.1;
    p.stereo.speckle_window_size = 0;
    p.stereo.block_size = 5;
    CDigiclopsStereoCamera cam;
    cam.setSensorLabel("TRINO");
    cam.setParameters(p);
    // Random texture; the right image is the left one shifted by d = 8 px:
    // depth = fx * B / d = 50 * 0.1 / 8 = 0.625 m.
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(7);
    cv::Mat left(48, 64, CV_8UC1), right(48, 64, CV_8UC1, cv::Scalar(0)), third(48, 64, CV_8UC1);
    for (int r = 0; r < 48; ++r)
    {
        for (int c = 0; c < 64; ++c)
        {
            left.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(rng.drawUniform32bit() & 0xFF);
            third.at<std::uint8_t>(r, c) = 0;
        }
    }
    left(cv::Rect(8, 0, 56, 48)).copyTo(right(cv::Rect(0, 0, 56, 48)));
    std::vector<cv::Mat> channels(3);
    channels[static_cast<std::size_t>(p.channel_left)] = left;
    channels[static_cast<std::size_t>(p.channel_right)] = right;
    channels[static_cast<std::size_t>(p.channel_third)] = third;
    const auto frame = emslam::hwdrivers::interleave(channels, p.frameFormat());
    const auto t = mrpt::Clock::fromDouble(1700000001.0);
    const auto objs = cam.convertFrame(frame.data(), frame.size(), t);
    ASSERT_EQ(objs.size(), 3U);
    const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(objs[2]);
    ASSERT_TRUE(scan);
    EXPECT_EQ(scan->sensorLabel, "TRINO_3D");
    EXPECT_EQ(scan->timestamp, t);
    ASSERT_TRUE(scan->hasPoints3D);
    ASSERT_GT(scan->points3D_x.size(), 200U);
    std::vector<float> depth(scan->points3D_x.begin(), scan->points3D_x.end());
    std::nth_element(depth.begin(), depth.begin() + depth.size() / 2, depth.end());
    EXPECT_NEAR(depth[depth.size() / 2], 0.625, 0.02);
}
