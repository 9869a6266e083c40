// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/AppMain.h>
#include <emslam/apps/PlyFile.h>
#include <emslam/apps/SimApp.h>
#include <emslam/io/OpenCvStereoCalibration.h>
#include <emslam/io/TumTrajectory.h>
#include <emslam/sim/StereoSimulator.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <vector>

using emslam::apps::SimApp;
namespace fs = std::filesystem;

namespace
{
std::string readFile(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::vector<std::string> withProgram(std::vector<std::string> args)
{
    args.insert(args.begin(), "emslam-sim");
    return args;
}

void initApp(SimApp& app, const std::vector<std::string>& args)
{
    const auto a = withProgram(args);
    std::vector<const char*> argv;
    for (const auto& s : a)
    {
        argv.push_back(s.c_str());
    }
    app.initialize(static_cast<int>(argv.size()), argv.data());
}

std::vector<mrpt::obs::CObservationStereoImages::Ptr> readRawlog(const std::string& file)
{
    std::vector<mrpt::obs::CObservationStereoImages::Ptr> v;
    mrpt::io::CFileGZInputStream f(file);
    auto arch = mrpt::serialization::archiveFrom(f);
    while (true)
    {
        try
        {
            auto o = arch.ReadObject();
            v.push_back(std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(o));
        }
        catch (const mrpt::serialization::CExceptionEOF&)
        {
            break;
        }
    }
    return v;
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

const std::string HALL = "/config/sim/hall_double_loop.ini";
}  // namespace

TEST(SimApp, writesRawlogAndGroundTruthThatReadBack)
{
    const std::string out = emslam::test::makeTempDir("sim_app");
    SimApp app;
    initApp(
        app, {emslam::test::sourceDir() + HALL, "-o", out + "/h.rawlog", "--gt-out", out + "/h.tum",
              "--max-frames", "6", "--png", out + "/png", "--quiet"});
    app.run();
    EXPECT_EQ(app.frames_written, 6U);
    EXPECT_EQ(app.poses_written, 6U);
    EXPECT_EQ(countLines(out + "/h.tum"), 6U);
    EXPECT_TRUE(fs::exists(out + "/png/left_000005.png"));
    EXPECT_TRUE(fs::exists(out + "/png/right_000000.png"));
    EXPECT_FALSE(fs::exists(out + "/h.rawlog.partial"));

    const auto obs = readRawlog(out + "/h.rawlog");
    ASSERT_EQ(obs.size(), 6U);
    const auto gt = emslam::io::TumTrajectory::fromFile(out + "/h.tum");
    ASSERT_EQ(gt.size(), obs.size());
    for (std::size_t i = 0; i < obs.size(); ++i)
    {
        ASSERT_TRUE(obs[i]);
        EXPECT_TRUE(obs[i]->hasImageRight);
        EXPECT_EQ(obs[i]->sensorLabel, "STEREO");
        EXPECT_EQ(obs[i]->imageLeft.getWidth(), 320U);
        EXPECT_NEAR(obs[i]->rightCameraPose.x(), 0.10, 1e-12);
        EXPECT_NEAR(mrpt::Clock::toDouble(obs[i]->timestamp), gt.poses[i].t, 1e-5);
    }
    EXPECT_EQ(gt.poses[0].pose.norm(), 0.0);
    EXPECT_GT(gt.poses[5].pose.norm(), 0.3);
}

// --video writes the frames side by side (FFV1: exactly), --video-calibration
// the rawlog's calibration; a bad codec or calibration name is a usage error.
TEST(SimApp, videoHoldsTheRawlogsFramesSideBySide)
{
    const std::string out = emslam::test::makeTempDir("sim_app_video");
    SimApp app;
    initApp(
        app, {emslam::test::sourceDir() + HALL, "-o", out + "/h.rawlog", "--max-frames", "4",
              "--video", out + "/h.mkv", "--video-calibration", out + "/h.yml", "--quiet"});
    app.run();
    EXPECT_FALSE(fs::exists(out + "/h.partial.mkv"));
    const auto obs = readRawlog(out + "/h.rawlog");
    ASSERT_EQ(obs.size(), 4U);
    cv::VideoCapture cap(out + "/h.mkv", cv::CAP_FFMPEG);
    ASSERT_TRUE(cap.isOpened());
    EXPECT_DOUBLE_EQ(cap.get(cv::CAP_PROP_FPS), 5.0);  // the world's [Simulation] fps
    cv::Mat frame, grey;
    std::size_t k = 0;
    for (; cap.read(frame); ++k)
    {
        ASSERT_LT(k, obs.size());
        cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
        ASSERT_EQ(grey.cols, 640);
        EXPECT_EQ(
            cv::norm(grey.colRange(0, 320), obs[k]->imageLeft.asCvMatRef(), cv::NORM_INF), 0.0);
        EXPECT_EQ(
            cv::norm(grey.colRange(320, 640), obs[k]->imageRight.asCvMatRef(), cv::NORM_INF), 0.0);
    }
    EXPECT_EQ(k, 4U);
    const auto cam = emslam::io::loadOpenCvStereoCalibration(out + "/h.yml");
    EXPECT_EQ(cam.leftCamera.ncols, 320U);
    EXPECT_DOUBLE_EQ(cam.leftCamera.fx(), obs[0]->leftCamera.fx());
    EXPECT_DOUBLE_EQ(cam.leftCamera.cx(), obs[0]->leftCamera.cx());
    EXPECT_NEAR(cam.rightCameraPose.x, obs[0]->rightCameraPose.x(), 1e-15);

    SimApp bad;
    emslam::test::expectThrowContaining(
        [&]
        {
            initApp(
                bad, {emslam::test::sourceDir() + HALL, "-o", out + "/b.rawlog", "--video",
                      out + "/b.avi", "--video-codec", "FFV"});
        },
        {"--video-codec"});
    emslam::test::expectThrowContaining(
        [&]
        {
            initApp(
                bad, {emslam::test::sourceDir() + HALL, "-o", out + "/b.rawlog", "--video",
                      out + "/b.avi", "--video-calibration", out + "/c.txt"});
        },
        {"--video-calibration", ".yml"});
}

TEST(SimApp, writesTheTrueSurfacesAndFloorPlanTheFramesSaw)
{
    const std::string out = emslam::test::makeTempDir("sim_app_truth");
    SimApp app;
    initApp(
        app, {emslam::test::sourceDir() + HALL, "-o", out + "/h.rawlog", "--max-frames", "6",
              "--map-gt-out", out + "/ref.ply", "--map-gt-spacing", "0.03", "--map-gt-range", "8",
              "--grid-gt-out", out + "/plan.gridmap", "--grid-config",
              emslam::test::sourceDir() + "/config/mapper/3dof-low-structured.ini", "--quiet"});
    app.run();
    const auto ref = emslam::apps::loadPly(out + "/ref.ply");
    EXPECT_EQ(ref.points.size(), app.reference_points);
    EXPECT_GT(ref.points.size(), 10000U);
    EXPECT_DOUBLE_EQ(ref.spacing, 0.03);
    ASSERT_EQ(ref.normals.size(), ref.points.size());
    ASSERT_EQ(ref.seen_range.size(), ref.points.size());
    for (std::size_t i = 0; i < ref.points.size(); ++i)
    {
        // The hall's floor is 1 m below the first camera (y down), its
        // ceiling 2.5 m above; the first frames look along +z at the wall
        // 21 m ahead, out of range.
        const auto& p = ref.points[i];
        ASSERT_GE(p.y, -2.5F - 1e-4F);
        ASSERT_LE(p.y, 1.0F + 1e-4F);
        ASSERT_GT(p.z, 0.0F);
        ASSERT_LE(ref.seen_range[i], 8.0F);
    }
    mrpt::io::CFileGZInputStream f(out + "/plan.gridmap");
    mrpt::maps::COccupancyGridMap2D plan;
    mrpt::serialization::archiveFrom(f) >> plan;
    EXPECT_NEAR(plan.getResolution(), 0.1, 1e-6);
    std::size_t occupied = 0;
    for (unsigned cy = 0; cy < plan.getSizeY(); ++cy)
    {
        for (unsigned cx = 0; cx < plan.getSizeX(); ++cx)
        {
            occupied += plan.getCell(cx, cy) < 0.5F ? 1 : 0;
        }
    }
    EXPECT_EQ(occupied, app.floor_plan_occupied);
    // The side walls 2 m left and right of the path (grid Y = left), seen
    // from the start on: occupied cells there, none in the free middle.
    EXPECT_GT(occupied, 40U);
    EXPECT_GT(plan.getPos(4.05F, 1.95F) < 0.5F || plan.getPos(4.05F, 2.05F) < 0.5F, 0);
    EXPECT_GT(plan.getPos(4.05F, 0.05F), 0.5F);
}

TEST(SimApp, sameSeedSameBytesOtherSeedOtherBytes)
{
    const std::string out = emslam::test::makeTempDir("sim_app_det");
    const std::string world = emslam::test::sourceDir() + HALL;
    for (const char* name : {"a", "b", "c"})
    {
        SimApp app;
        initApp(
            app, {world, "-o", out + "/" + name + ".rawlog", "--gt-out", out + "/" + name + ".tum",
                  "--max-frames", "4", "--seed", std::string(name) == "c" ? "5" : "4", "-q"});
        app.run();
    }
    EXPECT_EQ(readFile(out + "/a.rawlog"), readFile(out + "/b.rawlog"));
    EXPECT_EQ(readFile(out + "/a.tum"), readFile(out + "/b.tum"));
    EXPECT_NE(readFile(out + "/a.rawlog"), readFile(out + "/c.rawlog"));
}

TEST(SimApp, badIniFailsNamingTheKeyAndLeavesNoOutput)
{
    const std::string out = emslam::test::makeTempDir("sim_app_bad");
    const std::string good = readFile(emslam::test::sourceDir() + HALL);
    struct Case
    {
        std::string from, to, key;
    };
    const std::vector<Case> cases{
        {"type = building", "type = spaceship", "[World] type"},
        {"baseline = 0.10", "baseline = -0.10", "[Camera] baseline"},
        {"waypoints = 5 4; 23 4; 23 12; 5 12", "waypoints =", "[Trajectory] waypoints"},
    };
    for (const auto& c : cases)
    {
        std::string text = good;
        const auto pos = text.find(c.from);
        ASSERT_NE(pos, std::string::npos) << c.from;
        text.replace(pos, c.from.size(), c.to);
        const std::string ini = out + "/bad.ini";
        emslam::test::writeFile(ini, text);
        SimApp app;
        initApp(app, {ini, "-o", out + "/bad.rawlog", "-q"});
        emslam::test::expectThrowContaining([&] { app.run(); }, {c.key, "bad.ini"});
        EXPECT_FALSE(fs::exists(out + "/bad.rawlog"));
        EXPECT_FALSE(fs::exists(out + "/bad.rawlog.partial"));

        // Through the real main body: exit code 1.
        auto a = withProgram({ini, "-o", out + "/bad.rawlog", "-q"});
        std::vector<char*> argv;
        for (auto& s : a)
        {
            argv.push_back(s.data());
        }
        EXPECT_EQ(
            emslam::apps::appMain<SimApp>("emslam-sim", static_cast<int>(argv.size()), argv.data()),
            1);
    }
    // An unknown element type.
    emslam::test::writeFile(
        out + "/el.ini", good + "\n[Element_x]\ntype = cone\nmin = 0 0 0\nmax = 1 1 1\n");
    SimApp app;
    initApp(app, {out + "/el.ini", "-o", out + "/el.rawlog", "-q"});
    emslam::test::expectThrowContaining([&] { app.run(); }, {"[Element_x] type", "cone"});
    // Bad command lines.
    SimApp app2;
    EXPECT_THROW(initApp(app2, {out + "/missing.ini", "-o", out + "/x.rawlog"}), std::exception);
    EXPECT_THROW(
        initApp(app2, {out + "/el.ini", "-o", out + "/x.rawlog", "--max-frames", "-1"}),
        std::invalid_argument);
}

// A world that repeats a key or a section is refused naming both lines, both
// by emslam-sim and by the simulator library (the grabber's world_file).
TEST(SimApp, repeatedWorldKeyOrSectionIsRefusedNamingBothLines)
{
    const std::string out = emslam::test::makeTempDir("sim_app_dup");
    const std::string good = readFile(emslam::test::sourceDir() + HALL);
    const auto lines = static_cast<std::size_t>(std::count(good.begin(), good.end(), '\n'));
    const auto first = good.find("[Simulation]\n");
    ASSERT_NE(first, std::string::npos);
    const auto first_line =
        1 + static_cast<std::size_t>(std::count(good.begin(), good.begin() + first, '\n'));
    const std::string ini = out + "/dup.ini";
    emslam::test::writeFile(ini, good + "[Simulation]\nfps = 1\n");
    const std::string expected = ini + ":" + std::to_string(lines + 1) +
                                 ": section [Simulation] repeated (first at " + ini + ":" +
                                 std::to_string(first_line) + ")";
    SimApp app;
    emslam::test::expectThrowContaining(
        [&] {
            initApp(app, {ini, "-o", out + "/dup.rawlog", "-q"});
        },
        {expected});
    emslam::test::expectThrowContaining(
        [&] { emslam::sim::StereoSimulator().loadFile(ini); }, {expected});
    EXPECT_FALSE(fs::exists(out + "/dup.rawlog"));
}

// A full disk (the rawlog's `.partial` file links to /dev/full): the error
// names the rawlog and the OS reason (MRPT's gz stream said only "Cannot
// write bytes to stream!"), and no rawlog is left.
TEST(SimApp, fullDiskNamesTheRawlogAndTheReason)
{
    const std::string out = emslam::test::makeTempDir("sim_app_full");
    emslam::test::putOnFullDisk(out + "/h.rawlog");
    SimApp app;
    initApp(
        app, {emslam::test::sourceDir() + HALL, "-o", out + "/h.rawlog", "--frames", "3", "-q"});
    emslam::test::expectThrowContaining(
        [&] { app.run(); }, {"cannot write '" + out + "/h.rawlog': No space left on device"});
    EXPECT_FALSE(fs::exists(out + "/h.rawlog"));
}

// `-o` naming a FIFO (as `/dev/null` would be) is refused before any
// rendering and left as it is; a symbolic link is written through.
TEST(SimApp, outputFifoIsRefusedAndASymbolicLinkIsWrittenThrough)
{
    const std::string out = emslam::test::makeTempDir("sim_app_special");
    const std::string world = emslam::test::sourceDir() + HALL;
    const std::string fifo = out + "/pipe.rawlog";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    {
        SimApp app;
        initApp(app, {world, "-o", fifo, "--max-frames", "2", "-q"});
        emslam::test::expectThrowContaining(
            [&] { app.run(); }, {"pipe.rawlog' exists and is a FIFO", "not a regular file"});
        EXPECT_EQ(app.frames_written, 0U);
        EXPECT_TRUE(fs::is_fifo(fifo));
    }
    {
        // --gt-out naming a folder fails before the rawlog is written.
        SimApp app;
        initApp(app, {world, "-o", out + "/a.rawlog", "--gt-out", out, "--max-frames", "2", "-q"});
        emslam::test::expectThrowContaining([&] { app.run(); }, {"exists and is a folder"});
        EXPECT_FALSE(fs::exists(out + "/a.rawlog"));
    }
    fs::create_directory(out + "/runs");
    fs::create_symlink("runs/hall.rawlog", out + "/latest.rawlog");
    SimApp app;
    initApp(app, {world, "-o", out + "/latest.rawlog", "--max-frames", "2", "-q"});
    app.run();
    EXPECT_TRUE(fs::is_symlink(out + "/latest.rawlog"));
    EXPECT_EQ(readRawlog(out + "/runs/hall.rawlog").size(), 2U);
    EXPECT_FALSE(fs::exists(out + "/runs/hall.rawlog.partial"));
}

#ifdef EMSLAM_SIM_EXE
// Ctrl-C: the simulator stops after the current frame, keeps a complete,
// readable rawlog (and ground truth) of the frames rendered, says so, and
// exits 130 (128 + SIGINT); no `.partial` file is left.
TEST(SimApp, sigintKeepsACompleteRawlogOfTheFramesRendered)
{
    const std::string out = emslam::test::makeTempDir("sim_app_sigint");
    // Non-TTY progress prints one line per 10 %: interrupt after the first.
    const auto run = emslam::test::interruptedRun(
        EMSLAM_SIM_EXE,
        {emslam::test::sourceDir() + HALL, "-o", out + "/hall.rawlog", "--gt-out",
         out + "/hall.tum", "--max-frames", "400"},
        "frame ", SIGINT);
    ASSERT_TRUE(run.exited) << run.stderr_text;
    EXPECT_EQ(run.exit_code, 130) << run.stderr_text;
    EXPECT_NE(run.stderr_text.find("interrupted after "), std::string::npos) << run.stderr_text;
    const std::size_t frames = readRawlog(out + "/hall.rawlog").size();
    EXPECT_GE(frames, 40U);
    EXPECT_LT(frames, 400U);
    EXPECT_EQ(emslam::io::TumTrajectory::fromFile(out + "/hall.tum").size(), frames);
    EXPECT_FALSE(fs::exists(out + "/hall.rawlog.partial"));
    EXPECT_FALSE(fs::exists(out + "/hall.tum.partial"));
}
#endif
