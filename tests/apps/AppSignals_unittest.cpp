// SPDX-License-Identifier: BSD-3-Clause
// SIGHUP (a dropped ssh session) and SIGTERM stop every app that reads frames
// as Ctrl-C does: after the current frame, with the outputs of the frames
// done, exit 128 + the signal. On 80c9fba, SIGHUP left the mapper's output
// folder empty and emslam-odometry / emslam-stereo ignored every signal.
#include "SimulatedHall.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/TumTrajectory.h>

#include <gtest/gtest.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>

#if defined(EMSLAM_MAPPER_EXE) && defined(EMSLAM_ODOMETRY_EXE) && defined(EMSLAM_STEREO_EXE)

namespace fs = std::filesystem;

namespace
{
constexpr std::size_t FRAMES = 300;

std::string mapperConfig()
{
    return emslam::test::sourceDir() + "/config/mapper/3dof-low-structured.ini";
}

/** Exit code 128 + `signum`, promptly (loose: a loaded machine). */
void expectStoppedBy(const emslam::test::InterruptedRun& run, int signum)
{
    std::printf("exit %d, %.2f s after the signal\n", run.exit_code, run.seconds_to_exit);
    ASSERT_TRUE(run.exited) << run.stderr_text;
    EXPECT_EQ(run.exit_code, 128 + signum) << run.stderr_text;
    EXPECT_LT(run.seconds_to_exit, 30.0);
}
}  // namespace

TEST(AppSignals, sighupStopsTheMapperWithEveryOutput)
{
    const std::string out = emslam::test::makeTempDir("signals_mapper");
    const auto run = emslam::test::interruptedRun(
        EMSLAM_MAPPER_EXE, {mapperConfig(), emslam::test::simulatedHall(FRAMES), "--out", out},
        "frame ", SIGHUP);
    expectStoppedBy(run, SIGHUP);
    const auto slam = emslam::io::TumTrajectory::fromFile(out + "/trajectory_slam.tum");
    EXPECT_GT(slam.size(), 0U);
    EXPECT_LT(slam.size(), FRAMES);
    for (const char* f : {"summary.json", "stats.csv", "map.ply", "report.html"})
    {
        EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
    }
}

TEST(AppSignals, sighupAndSigtermStopTheOdometryWithItsTrajectory)
{
    for (const int signum : {SIGHUP, SIGTERM})
    {
        const std::string out = emslam::test::makeTempDir("signals_odometry");
        const auto run = emslam::test::interruptedRun(
            EMSLAM_ODOMETRY_EXE, {emslam::test::simulatedHall(FRAMES), "-o", out + "/t.tum"},
            "frame 5:", signum);
        expectStoppedBy(run, signum);
        EXPECT_NE(run.stderr_text.find("interrupted after "), std::string::npos) << run.stderr_text;
        const auto t = emslam::io::TumTrajectory::fromFile(out + "/t.tum");
        EXPECT_GE(t.size(), 6U);
        EXPECT_LT(t.size(), FRAMES);
    }
}

TEST(AppSignals, sighupStopsStereoWithACompleteRawlog)
{
    const std::string out = emslam::test::makeTempDir("signals_stereo");
    const auto run = emslam::test::interruptedRun(
        EMSLAM_STEREO_EXE,
        {emslam::test::simulatedHall(FRAMES), "--out-rawlog", out + "/scans.rawlog"},
        "frame 5:", SIGHUP);
    expectStoppedBy(run, SIGHUP);
    EXPECT_TRUE(fs::exists(out + "/scans.rawlog"));
    EXPECT_FALSE(fs::exists(out + "/scans.rawlog.partial"));
}

TEST(AppSignals, sighupStopsTheSimulatorWithACompleteRawlog)
{
    const std::string out = emslam::test::makeTempDir("signals_sim");
    const auto run = emslam::test::interruptedRun(
        EMSLAM_SIM_EXE,
        {emslam::test::sourceDir() + "/config/sim/hall_double_loop.ini", "-o", out + "/hall.rawlog",
         "--gt-out", out + "/hall.tum", "--max-frames", "400"},
        "frame ", SIGHUP);
    expectStoppedBy(run, SIGHUP);
    EXPECT_TRUE(fs::exists(out + "/hall.rawlog"));
    EXPECT_FALSE(fs::exists(out + "/hall.rawlog.partial"));
    EXPECT_GT(emslam::io::TumTrajectory::fromFile(out + "/hall.tum").size(), 0U);
}

#endif
