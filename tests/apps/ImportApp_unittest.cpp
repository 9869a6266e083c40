// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/ImportApp.h>
#include <emslam/io/KittiSequence.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

using emslam::apps::ImportApp;
namespace fs = std::filesystem;

using emslam::test::writeFile;

namespace
{
std::string readFile(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void initApp(ImportApp& app, std::vector<std::string> args)
{
    args.insert(args.begin(), "emslam-import");
    std::vector<const char*> argv;
    for (const auto& a : args)
    {
        argv.push_back(a.c_str());
    }
    app.initialize(static_cast<int>(argv.size()), argv.data());
}

/** Every object of an observations-only rawlog. */
std::vector<mrpt::serialization::CSerializable::Ptr> readRawlog(const std::string& file)
{
    std::vector<mrpt::serialization::CSerializable::Ptr> objs;
    mrpt::io::CFileGZInputStream f(file);
    auto arch = mrpt::serialization::archiveFrom(f);
    while (true)
    {
        try
        {
            objs.push_back(arch.ReadObject());
        }
        catch (const mrpt::serialization::CExceptionEOF&)
        {
            break;
        }
    }
    return objs;
}

std::size_t countLines(const std::string& file)
{
    std::ifstream f(file);
    std::size_t n = 0;
    for (std::string l; std::getline(f, l);)
    {
        ++n;
    }
    return n;
}

std::string frameName(const std::string& dir, const char* sub, int i)
{
    char name[16];
    std::snprintf(name, sizeof(name), "%06d.png", i);
    return dir + "/" + sub + "/" + name;
}

/** A tiny valid KITTI sequence (`n` frames) in `root/seq`, poses in `root/poses.txt`. */
std::string writeKitti(const std::string& root, int n)
{
    std::string dir = root + "/seq";
    fs::create_directories(dir + "/image_0");
    fs::create_directories(dir + "/image_1");
    writeFile(
        dir + "/calib.txt", "P0: 50 0 16 0 0 50 10 0 0 0 1 0\nP1: 50 0 16 -25 0 50 10 0 0 0 1 0\n");
    std::string times, poses;
    for (int i = 0; i < n; i++)
    {
        times += std::to_string(0.1 * i) + "\n";
        poses += "1 0 0 0 0 1 0 0 0 0 1 " + std::to_string(i) + "\n";
        for (const char* sub : {"image_0", "image_1"})
        {
            cv::imwrite(frameName(dir, sub, i), cv::Mat(20, 32, CV_8UC1, cv::Scalar(i)));
        }
    }
    writeFile(dir + "/times.txt", times);
    writeFile(root + "/poses.txt", poses);
    return dir;
}

/** Observation timestamps [s] of a rawlog of stereo observations. */
std::vector<double> stereoTimes(const std::vector<mrpt::serialization::CSerializable::Ptr>& objs)
{
    std::vector<double> t;
    for (const auto& o : objs)
    {
        const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(o);
        t.push_back(obs ? mrpt::Clock::toDouble(obs->timestamp) : -1.0);
    }
    return t;
}

bool equalImages(const cv::Mat& a, const cv::Mat& b)
{
    return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

bool hasPartialFiles(const std::string& dir)
{
    for (const auto& e : fs::directory_iterator(dir))
    {
        if (e.path().extension() == ".partial")
        {
            return true;
        }
    }
    return false;
}
}  // namespace

TEST(ImportApp, importsRealKittiWithStep)
{
    EMSLAM_REQUIRE_TEST_DATA(seq, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    const std::string out = emslam::test::makeTempDir("import_kitti");
    ImportApp app;
    initApp(
        app, {"kitti", seq, "--poses", poses, "-o", out + "/k06.rawlog", "--gt-out",
              out + "/k06.tum", "--step", "10", "--quiet"});
    app.run();
    EXPECT_EQ(app.frames_written, 6U);  // frames 0, 10, ..., 50
    EXPECT_EQ(app.poses_written, 6U);
    EXPECT_EQ(app.frames_without_gt, 0U);
    EXPECT_EQ(app.output_bytes, fs::file_size(out + "/k06.rawlog"));
    EXPECT_FALSE(hasPartialFiles(out));

    const auto objs = readRawlog(out + "/k06.rawlog");
    ASSERT_EQ(objs.size(), 6U);
    const auto gt = emslam::io::TumTrajectory::fromFile(out + "/k06.tum");
    ASSERT_EQ(gt.size(), 6U);
    EXPECT_EQ(countLines(out + "/k06.tum"), 6U);
    double last_t = -1;
    for (std::size_t k = 0; k < objs.size(); k++)
    {
        const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(objs[k]);
        ASSERT_TRUE(obs) << objs[k]->GetRuntimeClass()->className;
        EXPECT_TRUE(obs->hasImageRight);
        EXPECT_EQ(obs->sensorLabel, "STEREO");
        EXPECT_EQ(obs->imageLeft.getWidth(), 1226U);
        EXPECT_EQ(obs->imageRight.getHeight(), 370U);
        EXPECT_FALSE(obs->imageLeft.isExternallyStored());
        const auto cam = obs->getStereoCameraParams();
        EXPECT_NEAR(cam.rightCameraPose.x, 0.5372, 1e-4);
        EXPECT_NEAR(cam.leftCamera.fx(), 707.0912, 1e-9);
        const double t = mrpt::Clock::toDouble(obs->timestamp);
        EXPECT_GT(t, last_t);
        last_t = t;
        EXPECT_NEAR(gt.poses[k].t, t, 1e-6);
    }
    // GT relative to the first imported frame: identity first, then ~1.2 m per frame forward.
    const std::string first_line = emslam::io::TumTrajectory::formatLine(gt.poses[0]);
    EXPECT_EQ(first_line.substr(first_line.find(' ')), " 0 0 0 0 0 0 1");
    EXPECT_NEAR(gt.poses[5].pose.z(), 59.84, 0.01);
}

TEST(ImportApp, importsRealEurocRange)
{
    EMSLAM_REQUIRE_TEST_DATA(mav0, "euroc-v101-rest/mav0");
    EMSLAM_REQUIRE_TEST_DATA(gt, "euroc-v101-rest/groundtruth_left_cam.csv");
    const std::string out = emslam::test::makeTempDir("import_euroc");
    ImportApp app;
    initApp(
        app, {"euroc", mav0, "--gt", gt, "-o", out + "/e.rawlog", "--gt-out", out + "/e.tum",
              "--first", "5", "--last", "14", "--step", "3", "--label", "VI", "-q"});
    app.run();
    EXPECT_EQ(app.frames_written, 4U);  // 5, 8, 11, 14
    EXPECT_EQ(app.poses_written, 4U);
    const auto objs = readRawlog(out + "/e.rawlog");
    ASSERT_EQ(objs.size(), 4U);
    const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(objs[0]);
    ASSERT_TRUE(obs);
    EXPECT_EQ(obs->sensorLabel, "VI");
    EXPECT_NEAR(obs->rightCameraPose.x(), 0.110, 0.002);
    const auto traj = emslam::io::TumTrajectory::fromFile(out + "/e.tum");
    ASSERT_EQ(traj.size(), 4U);
    EXPECT_NEAR(traj.poses[0].t, mrpt::Clock::toDouble(obs->timestamp), 1e-6);
    EXPECT_LT(traj.poses[3].pose.translation().norm(), 0.003);  // at rest
}

TEST(ImportApp, importsSyntheticTumRgbd)
{
    const std::string root = emslam::test::makeTempDir("import_tum");
    const std::string dir = root + "/rgbd";
    fs::create_directories(dir + "/rgb");
    fs::create_directories(dir + "/depth");
    std::string rgb, depth, gt;
    for (int i = 0; i < 3; i++)
    {
        const std::string t = std::to_string(100 + i) + ".000000";
        const std::string td = std::to_string(100 + i) + ".010000";
        rgb += t + " rgb/" + t + ".png\n";
        depth += td + " depth/" + td + ".png\n";
        gt += t + " " + std::to_string(i) + " 0 0 0 0 0 1\n";
        cv::imwrite(dir + "/rgb/" + t + ".png", cv::Mat(12, 16, CV_8UC3, cv::Scalar(i, 2, 3)));
        cv::imwrite(dir + "/depth/" + td + ".png", cv::Mat(12, 16, CV_16UC1, cv::Scalar(5000)));
    }
    writeFile(dir + "/rgb.txt", rgb);
    writeFile(dir + "/depth.txt", depth);
    writeFile(dir + "/groundtruth.txt", gt);

    ImportApp app;
    initApp(
        app, {"tum", dir, "-o", root + "/t.rawlog", "--gt-out", root + "/t.tum", "--intrinsics",
              "100,101,8,6", "--first", "1", "-q"});
    app.run();
    EXPECT_EQ(app.frames_written, 2U);
    EXPECT_EQ(app.poses_written, 2U);
    const auto objs = readRawlog(root + "/t.rawlog");
    ASSERT_EQ(objs.size(), 2U);
    const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(objs[1]);
    ASSERT_TRUE(obs);
    EXPECT_EQ(obs->sensorLabel, "RGBD");
    EXPECT_DOUBLE_EQ(obs->cameraParams.fy(), 101.0);
    EXPECT_TRUE(obs->hasRangeImage);
    EXPECT_NEAR(obs->rangeImage(3, 4) * obs->rangeUnits, 1.0, 1e-6);
    const auto traj = emslam::io::TumTrajectory::fromFile(root + "/t.tum");
    ASSERT_EQ(traj.size(), 2U);
    EXPECT_DOUBLE_EQ(traj.poses[0].t, 101.0);
    EXPECT_NEAR(traj.poses[1].pose.x(), 1.0, 1e-12);  // relative to frame 1 (x = 1)
}

TEST(ImportApp, poseCountMismatchLeavesNoOutput)
{
    const std::string root = emslam::test::makeTempDir("import_badposes");
    const std::string seq = writeKitti(root, 4);
    writeFile(root + "/poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n");
    ImportApp app;
    initApp(
        app, {"kitti", seq, "--gt", root + "/poses.txt", "-o", root + "/out.rawlog", "--gt-out",
              root + "/out.tum", "-q"});
    try
    {
        app.run();
        ADD_FAILURE() << "no exception";
    }
    catch (const std::exception& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(root + "/poses.txt"), std::string::npos) << msg;
    }
    EXPECT_FALSE(fs::exists(root + "/out.rawlog"));
    EXPECT_FALSE(fs::exists(root + "/out.tum"));
    EXPECT_FALSE(hasPartialFiles(root));
    EXPECT_EQ(app.frames_written, 0U);
}

TEST(ImportApp, failureMidwayKeepsPreviousOutputAndRemovesPartials)
{
    const std::string root = emslam::test::makeTempDir("import_midway");
    const std::string seq = writeKitti(root, 5);
    writeFile(frameName(seq, "image_1", 3), "not a png");  // open() passes, frame 3 fails
    writeFile(root + "/out.rawlog", "previous");
    ImportApp app;
    initApp(
        app, {"kitti", seq, "--gt", root + "/poses.txt", "-o", root + "/out.rawlog", "--gt-out",
              root + "/out.tum", "-q"});
    EXPECT_ANY_THROW(app.run());
    EXPECT_EQ(readFile(root + "/out.rawlog"), "previous");
    EXPECT_FALSE(fs::exists(root + "/out.tum"));
    EXPECT_FALSE(hasPartialFiles(root));

    // The same sequence up to frame 2 imports fine.
    ImportApp ok;
    initApp(
        ok, {"kitti", seq, "--gt", root + "/poses.txt", "-o", root + "/out.rawlog", "--gt-out",
             root + "/out.tum", "--last", "2", "-q"});
    ok.run();
    EXPECT_EQ(ok.frames_written, 3U);
    EXPECT_EQ(readRawlog(root + "/out.rawlog").size(), 3U);
    EXPECT_EQ(countLines(root + "/out.tum"), 3U);
}

TEST(ImportApp, badArgumentsThrow)
{
    const std::string root = emslam::test::makeTempDir("import_args");
    const std::string seq = writeKitti(root, 3);
    const std::string o = root + "/o.rawlog";
    const std::vector<std::vector<std::string>> bad = {
        {},                                                      // nothing
        {"kitti", seq},                                          // no -o
        {"kinect", seq, "-o", o},                                // unknown format
        {"kitti", seq, "-o", o, "--step", "0"},                  // step < 1
        {"kitti", seq, "-o", o, "--step", "two"},                // not a number
        {"kitti", seq, "-o", o, "--first", "2", "--last", "1"},  // empty range
        {"tum", seq, "-o", o, "--gt", "x.csv"},                  // tum reads groundtruth.txt
        {"tum", seq, "-o", o, "--poses", "p.txt"},               // old kitti spelling, tum
        {"kitti", seq, "-o", o, "--intrinsics", "1,2,3,4"},      // tum option
        {"tum", seq, "-o", o, "--intrinsics", "1,2,3"},          // 3 numbers
        {"kitti", seq, "-o", o, "--gt-out", root + "/g.tum"},    // no GT source
        {"euroc", seq, "-o", o, "--gt-out", root + "/g.tum"},    // no GT source
        {"kitti", seq, "-o", o, "--gt", "p", "--gt-out", o},     // same file
        {"kitti", seq, "-o", o, "--no-such-option"},             // unknown option
    };
    for (const auto& args : bad)
    {
        ImportApp app;
        std::string joined;
        for (const auto& a : args)
        {
            joined += a + " ";
        }
        EXPECT_THROW(initApp(app, args), std::invalid_argument) << joined;
    }
    // Range beyond the sequence: detected by run().
    for (const auto& r : std::vector<std::vector<std::string>>{{"--first", "3"}, {"--last", "3"}})
    {
        ImportApp app;
        std::vector<std::string> args = {"kitti", seq, "-o", o, "-q"};
        args.insert(args.end(), r.begin(), r.end());
        initApp(app, args);
        EXPECT_ANY_THROW(app.run());
        EXPECT_FALSE(fs::exists(o));
    }
    // Output folder missing.
    ImportApp app;
    initApp(app, {"kitti", seq, "-o", root + "/no/such/dir/o.rawlog", "-q"});
    EXPECT_ANY_THROW(app.run());
}

TEST(ImportApp, helpRequestsQuit)
{
    ImportApp app;
    testing::internal::CaptureStdout();
    initApp(app, {"--help"});
    const std::string text = testing::internal::GetCapturedStdout();
    EXPECT_TRUE(app.helpRequested());
    EXPECT_NE(text.find("--gt-out"), std::string::npos);
    EXPECT_NO_THROW(app.run());
    EXPECT_EQ(app.frames_written, 0U);
}

// The "pseudo-loop" of the KITTI 06 excerpt: forward on the even frames, back
// on the odd ones; the last written frame (1) is ~1.2 m from the first (0).
TEST(ImportApp, importsRealKittiPseudoLoopFrameList)
{
    EMSLAM_REQUIRE_TEST_DATA(seq, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    const std::string out = emslam::test::makeTempDir("import_kitti_loop");
    ImportApp app;
    initApp(
        app, {"kitti", seq, "--gt", poses, "-o", out + "/loop.rawlog", "--gt-out",
              out + "/loop.tum", "--frames", "0:50:2,49:1:-2", "-q"});
    ASSERT_EQ(app.frames.size(), 51U);
    app.run();
    EXPECT_TRUE(app.retimed);
    EXPECT_EQ(app.frames_written, 51U);
    EXPECT_EQ(app.poses_written, 51U);

    const auto objs = readRawlog(out + "/loop.rawlog");
    ASSERT_EQ(objs.size(), 51U);
    const auto t = stereoTimes(objs);
    const auto gt = emslam::io::TumTrajectory::fromFile(out + "/loop.tum");
    ASSERT_EQ(gt.size(), 51U);
    emslam::io::KittiSequence kitti;
    kitti.open(seq, poses);
    const double period = t[1] - t[0];
    EXPECT_NEAR(period, 0.1, 0.01);  // KITTI's median period, ~10 Hz
    EXPECT_NEAR(t[0], kitti.timestamp(0), 1e-6);
    for (std::size_t k = 0; k < objs.size(); k++)
    {
        if (k > 0)
        {
            EXPECT_GT(t[k], t[k - 1]) << k;
            EXPECT_NEAR(t[k] - t[0], static_cast<double>(k) * period, 1e-5) << k;
        }
        EXPECT_NEAR(gt.poses[k].t, t[k], 1e-6) << k;
        // Original pose of the listed frame, relative to frame 0.
        const auto expected = kitti.groundTruth(app.frames[k]) - kitti.groundTruth(0);
        EXPECT_NEAR((gt.poses[k].pose.translation() - expected.translation()).norm(), 0.0, 1e-6)
            << k;
    }
    // Output frame k holds input frame list[k].
    for (const std::size_t k : {0U, 1U, 25U, 26U, 49U, 50U})
    {
        const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(objs[k]);
        ASSERT_TRUE(obs);
        const cv::Mat expected =
            cv::imread(kitti.leftImageFile(app.frames[k]), cv::IMREAD_GRAYSCALE);
        EXPECT_TRUE(equalImages(obs->imageLeft.asCvMatRef(), expected))
            << "output frame " << k << " vs input frame " << app.frames[k];
    }
    const double gap = gt.poses[50].pose.translation().norm();
    std::cout << "pseudo-loop: ground-truth end-to-start distance " << gap << " m\n";
    EXPECT_GT(gap, 0.5);
    EXPECT_LT(gap, 2.5);
}

TEST(ImportApp, frameListKeepsTimesWhenIncreasingAndRetimesOtherwise)
{
    const std::string root = emslam::test::makeTempDir("import_framelist");
    const std::string seq = writeKitti(root, 6);  // frame i: pixels = i, times 0.1 * i
    const std::string o = root + "/o.rawlog";

    ImportApp inc;
    initApp(inc, {"kitti", seq, "-o", o, "--frames", "0, 2:3,5", "-q"});
    inc.run();
    EXPECT_FALSE(inc.retimed);
    const auto t_inc = stereoTimes(readRawlog(o));
    ASSERT_EQ(t_inc.size(), 4U);
    EXPECT_NEAR(t_inc[3] - t_inc[0], 0.5, 1e-6);  // frame 5's own time

    ImportApp back;
    initApp(back, {"kitti", seq, "-o", o, "--frames", "4,1:3,3:0:-3"});
    testing::internal::CaptureStderr();
    testing::internal::CaptureStdout();
    back.run();
    const std::string err = testing::internal::GetCapturedStderr();
    testing::internal::GetCapturedStdout();
    EXPECT_EQ(back.frames, (std::vector<std::size_t>{4, 1, 2, 3, 3, 0}));
    EXPECT_TRUE(back.retimed);
    EXPECT_NE(err.find("not increasing"), std::string::npos) << err;
    const auto objs = readRawlog(o);
    ASSERT_EQ(objs.size(), 6U);
    const auto t = stereoTimes(objs);
    for (std::size_t k = 0; k < objs.size(); k++)
    {
        EXPECT_NEAR(t[k] - t[0], 0.1 * static_cast<double>(k), 1e-5) << k;
        const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(objs[k]);
        ASSERT_TRUE(obs);
        EXPECT_EQ(obs->imageLeft.asCvMatRef().at<uint8_t>(3, 4), back.frames[k]) << k;
    }
}

TEST(ImportApp, badFrameListsThrowClearErrors)
{
    const std::string root = emslam::test::makeTempDir("import_badframes");
    const std::string seq = writeKitti(root, 3);
    const std::string o = root + "/o.rawlog";
    const auto init = [&](std::vector<std::string> extra)
    {
        std::vector<std::string> args = {"kitti", seq, "-o", o, "-q"};
        args.insert(args.end(), extra.begin(), extra.end());
        return [args]
        {
            ImportApp app;
            initApp(app, args);
        };
    };
    using emslam::test::expectThrowContaining;
    expectThrowContaining(init({"--frames", "5:"}), {"--frames item '5:'", "not a frame index"});
    expectThrowContaining(init({"--frames", "a"}), {"'a' is not a frame index", "A:B:STEP"});
    expectThrowContaining(init({"--frames", "0:10:0"}), {"'0:10:0'", "STEP must not be 0"});
    expectThrowContaining(init({"--frames", "0:10:-1"}), {"leads away from 10"});
    expectThrowContaining(init({"--frames", "1,,2"}), {"--frames item ''"});
    expectThrowContaining(init({"--frames", "1:2:3:4"}), {"expected N, A:B or A:B:STEP"});
    expectThrowContaining(init({"--frames", "-1"}), {"'-1' is not a frame index"});
    expectThrowContaining(
        init({"--frames", "0:2", "--step", "2"}), {"--frames cannot be combined with --first"});
    EXPECT_THROW(init({"--frames", "5:"})(), std::invalid_argument);

    ImportApp app;
    initApp(app, {"kitti", seq, "-o", o, "--frames", "0,3", "-q"});
    expectThrowContaining(
        [&] { app.run(); }, {"frame index 3 is out of range", "3 frames (indexes 0..2)"});
    EXPECT_FALSE(fs::exists(o));
}

TEST(ImportApp, realKittiFrameIndexBeyondTheSequence)
{
    EMSLAM_REQUIRE_TEST_DATA(seq, "kitti-odometry/sequences/06");
    const std::string out = emslam::test::makeTempDir("import_kitti_badindex");
    ImportApp app;
    initApp(app, {"kitti", seq, "-o", out + "/k.rawlog", "--frames", "0:50:2,51", "-q"});
    emslam::test::expectThrowContaining(
        [&] { app.run(); }, {"frame index 51 is out of range", "51 frames (indexes 0..50)"});
    EXPECT_FALSE(fs::exists(out + "/k.rawlog"));
}

// --gt-out naming a folder (or -o a FIFO) is found before the import, not
// after the rawlog was written.
TEST(ImportApp, badOutputPathsFailBeforeTheImport)
{
    const std::string root = emslam::test::makeTempDir("import_outputs");
    const std::string seq = writeKitti(root, 3);
    fs::create_directory(root + "/gt_folder");
    ImportApp app;
    initApp(
        app, {"kitti", seq, "--gt", root + "/poses.txt", "-o", root + "/out.rawlog", "--gt-out",
              root + "/gt_folder", "-q"});
    emslam::test::expectThrowContaining(
        [&] { app.run(); }, {"gt_folder' exists and is a folder", "not a regular file"});
    EXPECT_FALSE(fs::exists(root + "/out.rawlog"));
    EXPECT_FALSE(hasPartialFiles(root));

    ASSERT_EQ(::mkfifo((root + "/pipe.rawlog").c_str(), 0600), 0);
    ImportApp fifo;
    initApp(fifo, {"kitti", seq, "-o", root + "/pipe.rawlog", "-q"});
    emslam::test::expectThrowContaining([&] { fifo.run(); }, {"pipe.rawlog' exists and is a FIFO"});
    EXPECT_TRUE(fs::is_fifo(root + "/pipe.rawlog"));
}

#ifdef EMSLAM_IMPORT_EXE
// Ctrl-C: the importer stops after the current frame, keeps a complete,
// readable rawlog (and ground truth) of the frames imported, says so, and
// exits 130 (128 + SIGINT); no `.partial` file is left.
TEST(ImportApp, sigintKeepsACompleteRawlogOfTheFramesImported)
{
    constexpr int FRAMES = 200;
    const std::string root = emslam::test::makeTempDir("import_sigint");
    const std::string seq = writeKitti(root, FRAMES);
    // Noise images, slow to decode and compress: the import outlasts the signal.
    cv::Mat noise(240, 320, CV_8UC1);
    cv::randu(noise, 0, 255);
    cv::imwrite(frameName(seq, "image_0", 0), noise);
    for (int i = 0; i < FRAMES; i++)
    {
        for (const char* sub : {"image_0", "image_1"})
        {
            if (i > 0 || sub != std::string("image_0"))
            {
                fs::copy_file(
                    frameName(seq, "image_0", 0), frameName(seq, sub, i),
                    fs::copy_options::overwrite_existing);
            }
        }
    }
    writeFile(
        seq + "/calib.txt",
        "P0: 300 0 160 0 0 300 120 0 0 0 1 0\n"
        "P1: 300 0 160 -150 0 300 120 0 0 0 1 0\n");
    const auto run = emslam::test::interruptedRun(
        EMSLAM_IMPORT_EXE,
        {"kitti", seq, "--gt", root + "/poses.txt", "-o", root + "/out.rawlog", "--gt-out",
         root + "/out.tum"},
        "frame ", SIGINT);
    ASSERT_TRUE(run.exited) << run.stderr_text;
    EXPECT_EQ(run.exit_code, 130) << run.stderr_text;
    EXPECT_NE(run.stderr_text.find("interrupted after "), std::string::npos) << run.stderr_text;
    const std::size_t frames = readRawlog(root + "/out.rawlog").size();
    EXPECT_GE(frames, 20U);
    EXPECT_LT(frames, static_cast<std::size_t>(FRAMES));
    EXPECT_EQ(countLines(root + "/out.tum"), frames);
    EXPECT_FALSE(hasPartialFiles(root));
}
#endif

// An output that is a file of the dataset or the ground truth is refused
// before anything is written, and the file is left as it was (on 80c9fba
// both were overwritten, exit 0).
TEST(ImportApp, anOutputThatIsAFileOfTheDatasetIsRefused)
{
    const std::string root = emslam::test::makeTempDir("import_output_input");
    const std::string seq = writeKitti(root, 4);
    const std::string image = frameName(seq, "image_0", 2);
    const std::string before = readFile(image);
    ImportApp app;
    initApp(app, {"kitti", seq, "-o", image, "-q"});
    emslam::test::expectThrowContaining(
        [&] { app.run(); }, {"output rawlog '" + image + "' is a file of the dataset"});
    EXPECT_EQ(readFile(image), before);
    // The ground truth given and written under one name.
    std::string poses;
    for (int i = 0; i < 4; ++i)
    {
        poses += "1 0 0 " + std::to_string(0.1 * i) + " 0 1 0 0 0 0 1 0\n";
    }
    emslam::test::writeFile(root + "/poses.txt", poses);
    ImportApp gt;
    initApp(
        gt, {"kitti", seq, "--gt", root + "/poses.txt", "-o", root + "/o.rawlog", "--gt-out",
             root + "/poses.txt", "-q"});
    emslam::test::expectThrowContaining(
        [&] { gt.run(); }, {"--gt-out", "is the ground truth (--gt)"});
    EXPECT_EQ(readFile(root + "/poses.txt"), poses);
    EXPECT_FALSE(fs::exists(root + "/o.rawlog"));
}
