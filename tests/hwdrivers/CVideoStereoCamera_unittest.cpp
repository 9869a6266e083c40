// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/hwdrivers/CVideoStereoCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/io/EurocSequence.h>
#include <emslam/io/OpenCvStereoCalibration.h>
#include <emslam/sim/StereoVideoWriter.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/stereo/StereoRectifier.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <vector>

using emslam::hwdrivers::CVideoStereoCamera;
using emslam::hwdrivers::EndOfStream;
using emslam::test::expectThrowContaining;
using mrpt::config::CConfigFileMemory;

namespace
{
constexpr int W = 64;
constexpr int H = 48;

/** Frame k of a textured test sequence (left or right): random grey levels. */
cv::Mat testImage(int k, bool right)
{
    cv::Mat m(H, W, CV_8UC1);
    cv::RNG rng(static_cast<uint64_t>(1000 + 2 * k + (right ? 1 : 0)));
    rng.fill(m, cv::RNG::UNIFORM, 0, 256);
    return m;
}

/** A lossless side-by-side video of `n` test frames at `fps`. */
std::string sideBySideVideo(const std::string& dir, int n, double fps = 5.0)
{
    const std::string file = dir + "/sbs.avi";
    emslam::sim::StereoVideoWriter w(file, fps, cv::Size(W, H));
    for (int k = 0; k < n; ++k)
    {
        w.write(testImage(k, false), testImage(k, true));
    }
    w.close();
    return file;
}

/** A lossless single-camera video of the left or right test images. */
std::string monoVideo(const std::string& dir, int n, bool right)
{
    const std::string file = dir + (right ? "/right.mkv" : "/left.mkv");
    cv::VideoWriter w(
        file, cv::CAP_FFMPEG, cv::VideoWriter::fourcc('F', 'F', 'V', '1'), 10.0, cv::Size(W, H),
        false);
    EXPECT_TRUE(w.isOpened());
    for (int k = 0; k < n; ++k)
    {
        w.write(testImage(k, right));
    }
    return file;
}

/** An ideal rectified pair of the test size, baseline 0.1 m, in the
 * TStereoCamera INI form under `prefix`. */
std::string pinholeCalibrationIni(const std::string& prefix = "VIDEO_CALIB")
{
    std::string s;
    for (const char* side : {"_LEFT", "_RIGHT"})
    {
        s += "[" + prefix + side +
             "]\nresolution = [64 48]\ncx = 31.5\ncy = 23.5\nfx = 50\nfy = 50\n"
             "distortion_model = none\ndist = [0 0 0 0 0]\n";
    }
    s += "[" + prefix + "_LEFT2RIGHT_POSE]\npose_quaternion = [0.1 0 0 1 0 0 0]\n";
    return s;
}

std::string sensorSection(const std::string& keys)
{
    return "[V]\nsensorLabel = STEREO\n" + keys + "\n" + pinholeCalibrationIni();
}

std::vector<mrpt::obs::CObservationStereoImages::Ptr> stereoObservations(CVideoStereoCamera& cam)
{
    std::vector<mrpt::obs::CObservationStereoImages::Ptr> out;
    for (const auto& [t, o] : cam.getObservations())
    {
        auto s = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(o);
        EXPECT_TRUE(s);
        out.push_back(s);
    }
    return out;
}

double maxDifference(const mrpt::img::CImage& a, const cv::Mat& b)
{
    return cv::norm(a.asCvMatRef(), b, cv::NORM_INF);
}
}  // namespace

TEST(CVideoStereoCamera, isRegisteredForTheGrabbers)
{
    EXPECT_TRUE(mrpt::hwdrivers::CGenericSensor::createSensorPtr("CVideoStereoCamera"));
}

TEST(CVideoStereoCamera, loadsKeysAndRoundTrips)
{
    const CConfigFileMemory c(sensorSection(
        "source = /dev/video2\nsource_right = /dev/video3\nbackend = v4l2\ncapture_width = "
        "640\ncapture_height = 480\ncapture_fps = 30\nfourcc = MJPG\ntimestamps = now\n"
        "start_time = 12.5\nvideo_fps = 7.5\ngrayscale = false\nrectify = false\n"
        "rectify_alpha = 0.5\npose_z = 1.2\npose_yaw_deg = 90\n"));
    CVideoStereoCamera::TParameters p;
    p.loadFromConfigFile(c, "V");
    EXPECT_EQ(p.source, "/dev/video2");
    EXPECT_EQ(p.source_right, "/dev/video3");
    EXPECT_EQ(p.backend, "v4l2");
    EXPECT_EQ(p.capture_width, 640);
    EXPECT_EQ(p.capture_height, 480);
    EXPECT_EQ(p.capture_fps, 30.0);
    EXPECT_EQ(p.fourcc, "MJPG");
    EXPECT_EQ(p.timestamps, "now");
    EXPECT_EQ(p.start_time, 12.5);
    EXPECT_EQ(p.video_fps, 7.5);
    EXPECT_FALSE(p.grayscale);
    EXPECT_FALSE(p.rectify);
    EXPECT_EQ(p.rectify_alpha, 0.5);
    EXPECT_EQ(p.pose_z, 1.2);
    EXPECT_EQ(p.pose_yaw_deg, 90.0);
    EXPECT_EQ(p.stereo_camera.leftCamera.ncols, 64U);
    EXPECT_NEAR(emslam::stereo::baselineOf(p.stereo_camera), 0.1, 1e-12);

    CConfigFileMemory out;
    p.saveToConfigFile(out, "W");
    const CConfigFileMemory reparsed(out.getContent());
    CVideoStereoCamera::TParameters q;
    q.loadFromConfigFile(reparsed, "W");
    EXPECT_EQ(q.source, p.source);
    EXPECT_EQ(q.source_right, p.source_right);
    EXPECT_EQ(q.capture_fps, p.capture_fps);
    EXPECT_EQ(q.fourcc, p.fourcc);
    EXPECT_EQ(q.start_time, p.start_time);
    EXPECT_EQ(q.video_fps, p.video_fps);
    EXPECT_EQ(q.grayscale, p.grayscale);
    EXPECT_EQ(q.rectify_alpha, p.rectify_alpha);
    EXPECT_EQ(q.pose_yaw_deg, p.pose_yaw_deg);
    EXPECT_EQ(q.stereo_camera.leftCamera.fx(), 50.0);
}

// A lossless side-by-side file: every frame comes back exactly, stamped
// start_time + k / fps, and the end of the file is a clean EndOfStream.
TEST(CVideoStereoCamera, readsASideBySideFileExactlyAndEndsCleanly)
{
    const std::string dir = emslam::test::makeTempDir("video_cam_sbs");
    const std::string video = sideBySideVideo(dir, 4, 5.0);
    CVideoStereoCamera cam;
    cam.loadConfig(
        CConfigFileMemory(sensorSection("source = " + video + "\nstart_time = 1700000000\n")), "V");
    cam.initialize();
    EXPECT_TRUE(cam.stampsFromVideo());
    EXPECT_DOUBLE_EQ(cam.stampFps(), 5.0);
    // No process_rate: the file's own rate.
    EXPECT_DOUBLE_EQ(cam.getProcessRate(), 5.0);
    for (int k = 0; k < 4; ++k)
    {
        cam.doProcess();
    }
    EXPECT_THROW(cam.doProcess(), EndOfStream);
    EXPECT_EQ(cam.framesDelivered(), 4U);
    const auto obs = stereoObservations(cam);
    ASSERT_EQ(obs.size(), 4U);
    for (int k = 0; k < 4; ++k)
    {
        const auto& o = *obs[static_cast<std::size_t>(k)];
        EXPECT_EQ(o.sensorLabel, "STEREO");
        EXPECT_TRUE(o.hasImageRight);
        EXPECT_EQ(maxDifference(o.imageLeft, testImage(k, false)), 0.0) << k;
        EXPECT_EQ(maxDifference(o.imageRight, testImage(k, true)), 0.0) << k;
        EXPECT_NEAR(mrpt::Clock::toDouble(o.timestamp), 1700000000.0 + 0.2 * k, 1e-6);
        EXPECT_EQ(o.leftCamera.fx(), 50.0);
        EXPECT_NEAR(o.rightCameraPose.x(), 0.1, 1e-12);
    }
}

TEST(CVideoStereoCamera, readsTwoSourcesAsLeftAndRight)
{
    const std::string dir = emslam::test::makeTempDir("video_cam_two");
    const std::string left = monoVideo(dir, 3, false);
    const std::string right = monoVideo(dir, 3, true);
    CVideoStereoCamera cam;
    cam.loadConfig(
        CConfigFileMemory(sensorSection(
            "source = " + left + "\nsource_right = " + right +
            "\nprocess_rate = 50\ntimestamps = now\npose_z = 1.5\n")),
        "V");
    const auto before = mrpt::Clock::now();
    cam.initialize();
    EXPECT_FALSE(cam.stampsFromVideo());
    EXPECT_DOUBLE_EQ(cam.getProcessRate(), 50.0);
    for (int k = 0; k < 3; ++k)
    {
        cam.doProcess();
    }
    EXPECT_THROW(cam.doProcess(), EndOfStream);
    const auto obs = stereoObservations(cam);
    ASSERT_EQ(obs.size(), 3U);
    for (int k = 0; k < 3; ++k)
    {
        const auto& o = *obs[static_cast<std::size_t>(k)];
        EXPECT_EQ(maxDifference(o.imageLeft, testImage(k, false)), 0.0) << k;
        EXPECT_EQ(maxDifference(o.imageRight, testImage(k, true)), 0.0) << k;
        EXPECT_GE(o.timestamp, before);  // the wall clock
        EXPECT_NEAR(o.cameraPose.z(), 1.5, 1e-12);
    }
}

// A raw (distorted, toed-in) pair in an OpenCV file with T in millimetres:
// the images are rectified exactly as StereoRectifier does, the calibration
// is the rectified one with the baseline in metres.
TEST(CVideoStereoCamera, rectifiesWithAnOpenCvCalibrationInMillimetres)
{
    const std::string dir = emslam::test::makeTempDir("video_cam_rect");
    const std::string video = sideBySideVideo(dir, 2);
    mrpt::img::TStereoCamera raw;
    for (auto* c : {&raw.leftCamera, &raw.rightCamera})
    {
        c->ncols = W;
        c->nrows = H;
        c->setIntrinsicParamsFromValues(52, 51, 30, 25);
        c->distortion = mrpt::img::DistortionModel::plumb_bob;
        c->dist.fill(0);
        c->dist[0] = -0.05;
        c->dist[1] = 0.01;
    }
    raw.rightCameraPose =
        mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(0.12, 0.002, -0.001, 0.02, 0.01, -0.005))
            .asTPose();
    // Written in metres, then T rewritten in millimetres.
    emslam::io::saveOpenCvStereoCalibration(dir + "/m.yml", raw);
    {
        cv::FileStorage in(dir + "/m.yml", cv::FileStorage::READ);
        cv::Mat M1, D1, M2, D2, R, T;
        in["M1"] >> M1;
        in["D1"] >> D1;
        in["M2"] >> M2;
        in["D2"] >> D2;
        in["R"] >> R;
        in["T"] >> T;
        cv::FileStorage out(dir + "/mm.yml", cv::FileStorage::WRITE);
        out << "M1" << M1 << "D1" << D1 << "M2" << M2 << "D2" << D2 << "R" << R << "T"
            << cv::Mat(T * 1000.0);
    }
    CVideoStereoCamera cam;
    cam.loadConfig(
        CConfigFileMemory(
            "[V]\nsource = " + video + "\ncalibration_file = " + dir +
            "/mm.yml\ntranslation_scale = 0.001\nprocess_rate = 10\n"),
        "V");
    cam.initialize();
    cam.doProcess();
    const auto obs = stereoObservations(cam);
    ASSERT_EQ(obs.size(), 1U);
    const emslam::stereo::StereoRectifier ref(raw);
    cv::Mat rl, rr;
    ref.rectify(testImage(0, false), testImage(0, true), rl, rr);
    EXPECT_EQ(maxDifference(obs[0]->imageLeft, rl), 0.0);
    EXPECT_EQ(maxDifference(obs[0]->imageRight, rr), 0.0);
    EXPECT_EQ(obs[0]->leftCamera.distortion, mrpt::img::DistortionModel::none);
    EXPECT_NEAR(obs[0]->leftCamera.fx(), ref.rectifiedCamera().leftCamera.fx(), 1e-9);
    EXPECT_NEAR(obs[0]->rightCameraPose.x(), ref.rectifiedCamera().rightCameraPose.x, 1e-9);
    EXPECT_NEAR(obs[0]->rightCameraPose.x(), std::hypot(0.12, 0.002, 0.001), 1e-6);
    EXPECT_NEAR(obs[0]->rightCameraPose.y(), 0.0, 1e-12);
}

TEST(CVideoStereoCamera, missingDeviceOrFileFailsAtInitializeNamingIt)
{
    const std::string dir = emslam::test::makeTempDir("video_cam_missing");
    auto initWith = [&](const std::string& keys)
    {
        CVideoStereoCamera cam;
        cam.loadConfig(CConfigFileMemory(sensorSection(keys)), "V");
        cam.initialize();
    };
    expectThrowContaining(
        [&] { initWith("source = /dev/video77\n"); },
        {"section V", "source '/dev/video77'", "V4L2 device", "no such device"});
    expectThrowContaining(
        [&] { initWith("source = 63\n"); }, {"source '63'", "device index", "cannot open"});
    expectThrowContaining(
        [&] { initWith("source = " + dir + "/none.avi\n"); },
        {"source '" + dir + "/none.avi'", "file not found"});
    const std::string video = sideBySideVideo(dir, 1);
    expectThrowContaining(
        [&] { initWith("source = " + video + "\nsource_right = " + dir + "/r.avi\n"); },
        {"source_right '" + dir + "/r.avi'", "file not found"});
    // A file that is not a video.
    emslam::test::writeFile(dir + "/text.avi", "not a video\n");
    expectThrowContaining(
        [&] { initWith("source = " + dir + "/text.avi\n"); }, {"text.avi", "cannot open"});
}

TEST(CVideoStereoCamera, badCalibrationOrKeysThrowNamingTheKey)
{
    const std::string dir = emslam::test::makeTempDir("video_cam_badcal");
    auto load = [&](const std::string& text)
    {
        CVideoStereoCamera cam;
        cam.loadConfig(CConfigFileMemory(text), "V");
    };
    expectThrowContaining(
        [&] { load("[V]\nsource = x.avi\n"); },
        {"calibration_section = 'VIDEO_CALIB'", "missing section [VIDEO_CALIB_LEFT"});
    expectThrowContaining(
        [&] { load("[V]\nsource = x.avi\ncalibration_file = " + dir + "/none.yml\n"); },
        {"calibration_file", "none.yml", "file not found"});
    emslam::test::writeFile(
        dir + "/noT.yml",
        "%YAML:1.0\nM1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 50, 0, "
        "32, 0, 50, 24, 0, 0, 1 ]\nM2: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   "
        "data: [ 50, 0, 32, 0, 50, 24, 0, 0, 1 ]\nR: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n");
    expectThrowContaining(
        [&] { load("[V]\nsource = x.avi\ncalibration_file = " + dir + "/noT.yml\n"); },
        {"calibration_file", "noT.yml", "missing key T"});
    expectThrowContaining([&] { load(sensorSection("")); }, {"'source'", "mandatory"});
    expectThrowContaining(
        [&] { load(sensorSection("source = a.avi\ntimestamps = dataset\n")); },
        {"timestamps", "dataset"});
    expectThrowContaining(
        [&] { load(sensorSection("source = a.avi\nfourcc = MJPEG\n")); }, {"fourcc", "MJPEG"});
    expectThrowContaining(
        [&] { load(sensorSection("source = a.avi\nbackend = dshow\n")); }, {"backend", "dshow"});
    expectThrowContaining(
        [&] { load(sensorSection("source = a.avi\nrectify_alpha = 2\n")); }, {"rectify_alpha"});
    expectThrowContaining(
        [&] { load(sensorSection("source = a.avi\nstart_time = nan\n")); }, {"start_time"});
    expectThrowContaining(
        [&] { load(sensorSection("source = a.avi\ntranslation_scale = 0\n")); },
        {"translation_scale"});

    // The calibration is 64x48; a video of 2 x 40x30 fails at initialize(), naming both.
    {
        emslam::sim::StereoVideoWriter w(dir + "/small.avi", 5.0, cv::Size(40, 30));
        w.write(cv::Mat(30, 40, CV_8UC1, cv::Scalar(7)), cv::Mat(30, 40, CV_8UC1, cv::Scalar(9)));
    }
    CVideoStereoCamera cam;
    cam.loadConfig(CConfigFileMemory(sensorSection("source = " + dir + "/small.avi\n")), "V");
    expectThrowContaining(
        [&] { cam.initialize(); }, {"40x30", "64x48", "VIDEO_CALIB", "another size"});
}

// An OpenCV file without an image size takes the images' size.
TEST(CVideoStereoCamera, calibrationWithoutSizeTakesTheImageSize)
{
    const std::string dir = emslam::test::makeTempDir("video_cam_nosize");
    const std::string video = sideBySideVideo(dir, 1);
    emslam::test::writeFile(
        dir + "/c.yml",
        "%YAML:1.0\nK1: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]\nK2: [50, 0, 31.5, 0, 50, 23.5, 0, "
        "0, 1]\nD1: []\nD2: []\nR: [0, 0, 0]\nT: [-0.1, 0, 0]\n");
    CVideoStereoCamera cam;
    cam.loadConfig(
        CConfigFileMemory("[V]\nsource = " + video + "\ncalibration_file = " + dir + "/c.yml\n"),
        "V");
    EXPECT_EQ(cam.parameters().stereo_camera.leftCamera.ncols, 0U);
    cam.initialize();
    EXPECT_EQ(cam.outputCamera().leftCamera.ncols, 64U);
    EXPECT_EQ(cam.outputCamera().leftCamera.nrows, 48U);
    cam.doProcess();
    const auto obs = stereoObservations(cam);
    ASSERT_EQ(obs.size(), 1U);
    // Already rectified: the images pass unchanged.
    EXPECT_EQ(maxDifference(obs[0]->imageLeft, testImage(0, false)), 0.0);
}

// A GStreamer pipeline is a source too (skipped where GStreamer's base
// plugins are missing).
TEST(CVideoStereoCamera, readsAGStreamerPipelineToItsEnd)
{
    const std::string pipeline =
        "videotestsrc num-buffers=3 pattern=ball ! video/x-raw,format=GRAY8,width=128,height=48 "
        "! appsink";
    cv::VideoCapture probe(pipeline, cv::CAP_GSTREAMER);
    if (!probe.isOpened())
    {
        GTEST_SKIP() << "OpenCV cannot open a GStreamer videotestsrc pipeline here";
    }
    probe.release();
    CVideoStereoCamera cam;
    cam.loadConfig(CConfigFileMemory(sensorSection("source = " + pipeline + "\n")), "V");
    cam.initialize();
    EXPECT_FALSE(cam.stampsFromVideo());
    for (int k = 0; k < 3; ++k)
    {
        cam.doProcess();
    }
    EXPECT_THROW(cam.doProcess(), EndOfStream);
    EXPECT_EQ(stereoObservations(cam).size(), 3U);
}

TEST(CVideoStereoCamera, classifiesSources)
{
    using emslam::hwdrivers::classifyVideoSource;
    using K = emslam::hwdrivers::VideoSourceKind;
    EXPECT_EQ(classifyVideoSource("0"), K::DEVICE_INDEX);
    EXPECT_EQ(classifyVideoSource(" 12 "), K::DEVICE_INDEX);
    EXPECT_EQ(classifyVideoSource("/dev/video0"), K::DEVICE_PATH);
    EXPECT_EQ(classifyVideoSource("/dev/v4l/by-id/usb-cam-video-index0"), K::DEVICE_PATH);
    EXPECT_EQ(classifyVideoSource("v4l2src ! videoconvert ! appsink"), K::PIPELINE);
    EXPECT_EQ(classifyVideoSource("hall.avi"), K::FILE);
    EXPECT_EQ(classifyVideoSource("left_%04d.png"), K::FILE);
    EXPECT_EQ(classifyVideoSource("2024.mkv"), K::FILE);
}

// Colour sources: grey by default (OpenCV's BGR to grey), the colour images with
// grayscale = false.
TEST(CVideoStereoCamera, colourFramesAreGreyUnlessAskedForColour)
{
    const std::string dir = emslam::test::makeTempDir("video_cam_colour");
    cv::Mat left(H, W, CV_8UC3), right(H, W, CV_8UC3);
    cv::RNG rng(7);
    rng.fill(left, cv::RNG::UNIFORM, 0, 256);
    rng.fill(right, cv::RNG::UNIFORM, 0, 256);
    {
        emslam::sim::StereoVideoWriter w(dir + "/c.avi", 5.0, cv::Size(W, H), "FFV1", true);
        w.write(left, right);
    }
    for (const bool grey : {true, false})
    {
        CVideoStereoCamera cam;
        cam.loadConfig(
            CConfigFileMemory(sensorSection(
                "source = " + dir + "/c.avi\ngrayscale = " + (grey ? "true" : "false") + "\n")),
            "V");
        cam.initialize();
        cam.doProcess();
        const auto obs = stereoObservations(cam);
        ASSERT_EQ(obs.size(), 1U);
        cv::Mat l = left, r = right;
        if (grey)
        {
            cv::cvtColor(left, l, cv::COLOR_BGR2GRAY);
            cv::cvtColor(right, r, cv::COLOR_BGR2GRAY);
        }
        EXPECT_EQ(obs[0]->imageLeft.asCvMatRef().type(), grey ? CV_8UC1 : CV_8UC3);
        EXPECT_EQ(maxDifference(obs[0]->imageLeft, l), 0.0) << grey;
        EXPECT_EQ(maxDifference(obs[0]->imageRight, r), 0.0) << grey;
    }
}

// An image sequence declares no frame rate: video stamps need video_fps,
// which also overrides a file's own rate.
TEST(CVideoStereoCamera, imageSequenceNeedsVideoFpsForItsStamps)
{
    const std::string dir = emslam::test::makeTempDir("video_cam_seq");
    for (int k = 0; k < 3; ++k)
    {
        cv::Mat frame;
        cv::hconcat(testImage(k, false), testImage(k, true), frame);
        char name[64];
        std::snprintf(name, sizeof(name), "/sbs_%04d.png", k);
        ASSERT_TRUE(cv::imwrite(dir + name, frame));
    }
    const std::string source = "source = " + dir + "/sbs_%04d.png\n";
    {
        CVideoStereoCamera cam;
        cam.loadConfig(CConfigFileMemory(sensorSection(source)), "V");
        expectThrowContaining([&] { cam.initialize(); }, {"video_fps", "declares no frame rate"});
    }
    CVideoStereoCamera cam;
    cam.loadConfig(
        CConfigFileMemory(sensorSection(source + "video_fps = 4\nstart_time = 100\n")), "V");
    cam.initialize();
    for (int k = 0; k < 3; ++k)
    {
        cam.doProcess();
    }
    EXPECT_THROW(cam.doProcess(), EndOfStream);
    const auto obs = stereoObservations(cam);
    ASSERT_EQ(obs.size(), 3U);
    for (int k = 0; k < 3; ++k)
    {
        const auto& o = *obs[static_cast<std::size_t>(k)];
        EXPECT_EQ(maxDifference(o.imageLeft, testImage(k, false)), 0.0) << k;
        EXPECT_NEAR(mrpt::Clock::toDouble(o.timestamp), 100.0 + 0.25 * k, 1e-6);
    }
}

// Real raw stereo (EuRoC: distorted, not rectified, 11 cm baseline): the
// pairs as a side-by-side video with the calibration as an OpenCV file give
// the observations the EuRoC reader gives (rectify = false: the same raw
// images and calibration), and with rectify = true the StereoRectifier's pair.
TEST(CVideoStereoCamera, eurocPairsThroughAVideoMatchTheDatasetReader)
{
    EMSLAM_REQUIRE_TEST_DATA(mav0, "euroc-v101-rest/mav0");
    emslam::io::EurocSequence seq(mav0);
    const std::string dir = emslam::test::makeTempDir("video_cam_euroc");
    constexpr std::size_t N = 3;
    const auto& raw = seq.calibration();
    {
        emslam::sim::StereoVideoWriter w(
            dir + "/euroc.mkv", 20.0,
            cv::Size(
                static_cast<int>(raw.leftCamera.ncols), static_cast<int>(raw.leftCamera.nrows)));
        for (std::size_t i = 0; i < N; ++i)
        {
            const auto f = seq.frame(i);
            w.write(f.obs->imageLeft.asCvMatRef(), f.obs->imageRight.asCvMatRef());
        }
    }
    emslam::io::saveOpenCvStereoCalibration(dir + "/euroc.yml", raw);
    const emslam::stereo::StereoRectifier rectifier(raw);
    for (const bool rectify : {false, true})
    {
        CVideoStereoCamera cam;
        cam.loadConfig(
            CConfigFileMemory(
                "[V]\nsource = " + dir + "/euroc.mkv\ncalibration_file = " + dir +
                "/euroc.yml\nrectify = " + (rectify ? "true" : "false") + "\n"),
            "V");
        cam.initialize();
        for (std::size_t i = 0; i < N; ++i)
        {
            cam.doProcess();
        }
        const auto obs = stereoObservations(cam);
        ASSERT_EQ(obs.size(), N);
        for (std::size_t i = 0; i < N; ++i)
        {
            const auto ref = seq.frame(i).obs;
            cv::Mat l = ref->imageLeft.asCvMatRef(), r = ref->imageRight.asCvMatRef();
            if (rectify)
            {
                rectifier.rectify(ref->imageLeft.asCvMatRef(), ref->imageRight.asCvMatRef(), l, r);
            }
            EXPECT_EQ(maxDifference(obs[i]->imageLeft, l), 0.0) << i << " " << rectify;
            EXPECT_EQ(maxDifference(obs[i]->imageRight, r), 0.0) << i << " " << rectify;
        }
        const auto& c = rectify ? rectifier.rectifiedCamera() : raw;
        EXPECT_NEAR(obs[0]->leftCamera.fx(), c.leftCamera.fx(), 1e-9);
        EXPECT_NEAR(obs[0]->rightCamera.cx(), c.rightCamera.cx(), 1e-9);
        EXPECT_NEAR(obs[0]->leftCamera.dist[0], c.leftCamera.dist[0], 1e-15);
        const mrpt::poses::CPose3D a(mrpt::poses::CPose3DQuat(obs[0]->rightCameraPose));
        const mrpt::poses::CPose3D b(mrpt::poses::CPose3DQuat(c.rightCameraPose));
        EXPECT_LT(emslam::test::maxPoseDifference(a, b), 1e-12);
    }
}
