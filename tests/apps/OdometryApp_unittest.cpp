// SPDX-License-Identifier: BSD-3-Clause
#include "SimulatedHall.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/OdometryApp.h>
#include <emslam/io/KittiSequence.h>
#include <emslam/io/TrajectoryReader.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <limits>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace
{
void initApp(emslam::apps::OdometryApp& app, std::vector<std::string> args)
{
    args.insert(args.begin(), "emslam-odometry");
    std::vector<const char*> argv;
    for (const auto& a : args)
    {
        argv.push_back(a.c_str());
    }
    app.initialize(static_cast<int>(argv.size()), argv.data());
}

/** The first `n` frames of the KITTI 06 excerpt as a rawlog (embedded images). */
std::string writeKittiRawlog(const std::string& seq_dir, std::size_t n, const std::string& dir)
{
    const emslam::io::KittiSequence seq(seq_dir);
    const std::string file = dir + "/kitti06.rawlog";
    mrpt::io::CFileGZOutputStream out(file);
    auto arch = mrpt::serialization::archiveFrom(out);
    for (std::size_t i = 0; i < n; ++i)
    {
        arch << *seq.frame(i).obs;
    }
    return file;
}
/** Runs emslam-odometry on `rawlog` (the hall's [StereoMatcher] / [EgomotionEstimator])
 * into `out`; returns its stderr. */
std::string runOdometry(
    emslam::apps::OdometryApp& app, const std::string& rawlog, const std::string& out)
{
    initApp(
        app, {rawlog, "-o", out, "--config",
              emslam::test::sourceDir() + "/config/mapper/3dof-low-structured.ini", "--quiet"});
    return emslam::test::capturingStderr([&] { app.run(); });
}

/** The trajectory file holds `n` poses, strictly increasing in time. */
void expectStrictlyIncreasing(const std::string& tum_file, std::size_t n)
{
    const auto t = emslam::test::trajectoryTimes(tum_file);
    EXPECT_EQ(t.size(), n);
    for (std::size_t i = 1; i < t.size(); ++i)
    {
        EXPECT_GT(t[i], t[i - 1]) << "line " << i;
    }
}
}  // namespace

TEST(OdometryApp, missingArgumentsThrow)
{
    emslam::apps::OdometryApp app;
    EXPECT_ANY_THROW(initApp(app, {"-o", "x.tum"}));
    emslam::apps::OdometryApp app2;
    EXPECT_ANY_THROW(initApp(app2, {"x.rawlog"}));
}

TEST(OdometryApp, helpDoesNotRun)
{
    emslam::apps::OdometryApp app;
    initApp(app, {"--help"});
    EXPECT_TRUE(app.helpRequested());
    EXPECT_NO_THROW(app.run());
}

TEST(OdometryApp, missingRawlogThrowsNamingIt)
{
    emslam::apps::OdometryApp app;
    initApp(app, {"/nonexistent/in.rawlog", "-o", "/tmp/never.tum"});
    emslam::test::expectThrowContaining([&] { app.run(); }, {"/nonexistent/in.rawlog"});
}

TEST(OdometryApp, invalidEgomotionOverrideThrows)
{
    // Refused by initialize(), before the (missing) rawlog is looked at.
    emslam::apps::OdometryApp app;
    emslam::test::expectThrowContaining(
        [&]
        {
            initApp(
                app, {"/nonexistent/in.rawlog", "-o", "/tmp/never.tum", "--set",
                      "EgomotionEstimator.lwo_sigma_min=0"});
        },
        {"lwo_sigma_min", "(0, 1e6]"});
}

// End to end on the first KITTI 06 frames with the shipped config.
TEST(OdometryApp, kittiRawlogGivesTrajectory)
{
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    const std::string dir = emslam::test::makeTempDir("odometry_app");
    const std::size_t n = 8;
    const std::string rawlog = writeKittiRawlog(seq_dir, n, dir);
    const std::string out = dir + "/traj.tum";

    emslam::apps::OdometryApp app;
    initApp(
        app, {rawlog, "-o", out, "--config",
              emslam::test::sourceDir() + "/config/odometry/kitti.ini", "--max-frames", "6"});
    app.run();
    EXPECT_EQ(app.frames_processed, 6u);
    EXPECT_EQ(app.failures, 0u);
    EXPECT_GT(app.mean_final_matches, 50);

    const auto traj = emslam::io::TumTrajectory::fromFile(out);
    ASSERT_EQ(traj.size(), 6u);
    const auto gt = emslam::io::KittiSequence::readPosesFile(poses);
    // About 6 m driven in 5 steps: the end point within 2 %. Measured
    // 0.104 m with the shipped reprojection refinement, 0.062 m without it
    // (over the whole excerpt it lowers the drift, 0.83 -> 0.73 %).
    const double err = (traj.poses.back().pose - gt[5]).norm();
    EXPECT_LT(err, 0.12) << "end-point error " << err << " m";
    EXPECT_GT(traj.poses[1].t, traj.poses[0].t);
}

// A step that fails (here: a frame with textureless images) keeps the pose.
TEST(OdometryApp, failedStepKeepsPreviousPose)
{
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    const std::string dir = emslam::test::makeTempDir("odometry_app_fail");
    const emslam::io::KittiSequence seq(seq_dir);
    const std::string rawlog = dir + "/flat.rawlog";
    {
        mrpt::io::CFileGZOutputStream out(rawlog);
        auto arch = mrpt::serialization::archiveFrom(out);
        arch << *seq.frame(0).obs;
        auto flat = seq.frame(1).obs;
        const cv::Mat grey(
            static_cast<int>(seq.imageHeight()), static_cast<int>(seq.imageWidth()), CV_8UC1,
            cv::Scalar(100));
        flat->imageLeft = mrpt::img::CImage(grey, mrpt::img::DEEP_COPY);
        flat->imageRight = mrpt::img::CImage(grey, mrpt::img::DEEP_COPY);
        arch << *flat;
    }
    emslam::apps::OdometryApp app;
    initApp(
        app, {rawlog, "-o", dir + "/t.tum", "--config",
              emslam::test::sourceDir() + "/config/odometry/kitti.ini", "--quiet"});
    app.run();
    EXPECT_EQ(app.frames_processed, 2u);
    EXPECT_EQ(app.failures, 1u);
    ASSERT_EQ(app.trajectory.size(), 2u);
    EXPECT_TRUE(app.trajectory.poses[1].pose == mrpt::poses::CPose3D());
    // Its only step failed: a degenerate run (exit status 3), the trajectory still written.
    EXPECT_EQ(app.degenerate, "1 of 1 egomotion steps failed (100 %)");
    EXPECT_EQ(app.exitCode(), emslam::apps::EXIT_DEGENERATE);
    EXPECT_TRUE(mrpt::system::fileExists(dir + "/t.tum"));
}

// --trajectory-format: KITTI poses + times beside the TUM file, or alone at -o.
TEST(OdometryApp, writesKittiTrajectories)
{
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    const std::string dir = emslam::test::makeTempDir("odometry_app_kitti");
    const emslam::io::KittiSequence seq(seq_dir);
    const std::string rawlog = dir + "/k3.rawlog";
    {
        mrpt::io::CFileGZOutputStream out(rawlog);
        auto arch = mrpt::serialization::archiveFrom(out);
        for (std::size_t i = 0; i < 3; i++)
        {
            arch << *seq.frame(i).obs;
        }
    }
    const std::string cfg = emslam::test::sourceDir() + "/config/odometry/kitti.ini";
    emslam::apps::OdometryApp both;
    initApp(
        both, {"--rawlog", rawlog, "-o", dir + "/t.tum", "--config", cfg, "--quiet",
               "--trajectory-format", "both"});
    both.run();
    ASSERT_EQ(both.trajectory.size(), 3u);
    const auto tum = emslam::io::TumTrajectory::fromFile(dir + "/t.tum");
    const auto kitti = emslam::io::loadTrajectory(dir + "/t_kitti.txt");
    EXPECT_EQ(kitti.format, emslam::io::TrajectoryFormat::Kitti);
    EXPECT_EQ(kitti.times_file, dir + "/t_times.txt");
    ASSERT_EQ(tum.size(), 3u);
    ASSERT_EQ(kitti.trajectory.size(), 3u);
    for (std::size_t i = 0; i < 3; i++)
    {
        // UNIX times as the importer gives them, the same in both files.
        EXPECT_NEAR(kitti.trajectory.poses[i].t, seq.timestamp(i), 1e-6);
        EXPECT_NEAR(tum.poses[i].t, kitti.trajectory.poses[i].t, 1e-9);
        EXPECT_LT(
            emslam::test::maxPoseDifference(tum.poses[i].pose, kitti.trajectory.poses[i].pose),
            1e-9);
    }
    EXPECT_GT(kitti.trajectory.poses[2].pose.z(), 1.0);  // driving forward

    emslam::apps::OdometryApp only;
    initApp(
        only, {"--rawlog", rawlog, "-o", dir + "/k_kitti.txt", "--config", cfg, "--quiet",
               "--trajectory-format", "kitti"});
    only.run();
    EXPECT_TRUE(mrpt::system::fileExists(dir + "/k_times.txt"));
    EXPECT_FALSE(mrpt::system::fileExists(dir + "/k_kitti.tum"));
    EXPECT_EQ(emslam::io::loadTrajectory(dir + "/k_kitti.txt").trajectory.size(), 3u);

    emslam::apps::OdometryApp bad;
    emslam::test::expectThrowContaining(
        [&] {
            initApp(bad, {"--rawlog", rawlog, "-o", dir + "/x.tum", "--trajectory-format", "ply"});
        },
        {"--trajectory-format", "'ply'"});
}

// Frame 5's right image is 160x120 while its left is 320x240: the frame is
// skipped with a warning, as emslam-mapper does, and the trajectory written.
TEST(OdometryApp, rawlogWithOneBadFrameStillGivesTheTrajectory)
{
    const std::string dir = emslam::test::makeTempDir("odometry_bad_frame");
    const std::string rawlog = dir + "/bad_frame.rawlog";
    emslam::test::writeEditedHall(
        rawlog, 12,
        [](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
        {
            if (i == 5)
            {
                emslam::test::shrinkRightImage(stereo);
            }
        });
    emslam::apps::OdometryApp app;
    const std::string err = runOdometry(app, rawlog, dir + "/t.tum");
    EXPECT_EQ(app.frames_processed, 11U);
    EXPECT_EQ(app.skipped.unusable, 1U);
    EXPECT_EQ(app.skipped.total(), 1U);
    EXPECT_NE(
        err.find("emslam-odometry: warning: skipping unusable observation at record 5: stereo "
                 "observation 'STEREO': left image is 320x240 but right image is 160x120\n"),
        std::string::npos)
        << err;
    expectStrictlyIncreasing(dir + "/t.tum", 11);
}

// A repeated stamp (frame 4), one 1 s back (frame 7) and the stamp a NaN
// becomes (frame 9): skipped and counted; the trajectory increases.
TEST(OdometryApp, badTimestampsAreSkippedAndTheTrajectoryIncreases)
{
    const std::string dir = emslam::test::makeTempDir("odometry_stamps");
    const std::string rawlog = dir + "/stamps.rawlog";
    mrpt::Clock::time_point previous;
    emslam::test::writeEditedHall(
        rawlog, 12,
        [&](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
        {
            const auto own = stereo.timestamp;
            if (i == 4)
            {
                stereo.timestamp = previous;
            }
            if (i == 7)
            {
                stereo.timestamp = own - std::chrono::seconds(1);
            }
            if (i == 9)
            {
                stereo.timestamp = mrpt::Clock::time_point(mrpt::Clock::duration(
                    std::numeric_limits<std::int64_t>::min() + 116444736000000000LL));
            }
            previous = own;
        });
    emslam::apps::OdometryApp app;
    const std::string err = runOdometry(app, rawlog, dir + "/t.tum");
    EXPECT_EQ(app.frames_processed, 9U);
    EXPECT_EQ(app.skipped.bad_stamps, 3U);
    ASSERT_EQ(app.skipped_reasons.size(), 3U);
    EXPECT_EQ(
        app.skipped_reasons[0],
        "record 4: its timestamp 1700000000.600000000 is the same as record 3's (the last frame "
        "used)");
    EXPECT_EQ(
        app.skipped_reasons[1],
        "record 7: its timestamp 1700000000.400000000 is 0.8 s before record 6's (the last frame "
        "used)");
    EXPECT_EQ(app.skipped_reasons[2], "record 9: its timestamp 9.223372037e+11 s is after 2100");
    EXPECT_NE(err.find("emslam-odometry: warning: skipping frame at record 7: "), std::string::npos)
        << err;
    expectStrictlyIncreasing(dir + "/t.tum", 9);
}

// Frames of a 640x480 camera between 320x240 ones are skipped; a rawlog
// whose camera changes for good is followed as far as the first camera goes.
TEST(OdometryApp, framesOfAnotherCameraAreSkipped)
{
    const std::string dir = emslam::test::makeTempDir("odometry_camera");
    for (const bool for_good : {false, true})
    {
        const std::string rawlog = dir + (for_good ? "/for_good.rawlog" : "/interleaved.rawlog");
        emslam::test::writeEditedHall(
            rawlog, 12,
            [&](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
            {
                if (for_good ? i >= 8 : (i == 3 || i == 6))
                {
                    emslam::test::resizeStereoFrame(stereo, 640, 480);
                }
            });
        emslam::apps::OdometryApp app;
        const std::string out = rawlog + ".tum";
        const std::string err = runOdometry(app, rawlog, out);
        EXPECT_EQ(app.frames_processed, for_good ? 8U : 10U);
        EXPECT_EQ(app.skipped.camera_changes, for_good ? 4U : 2U);
        EXPECT_EQ(app.failures, 0U);
        EXPECT_EQ(app.exitCode(), 0);
        const std::string end =
            for_good ? "4 frames skipped: camera changed from 320x240 (fx 200, fy 200, cx 159.5, "
                       "cy 119.5, baseline 0.1 m) to 640x480 (fx 400, fy 400, cx 319, cy "
                       "239, baseline 0.1 m) at record 8; only the 8 frames before it were used"
                     : "2 frames skipped: their camera differed from the session's 320x240 (fx "
                       "200, fy 200, cx 159.5, cy 119.5, baseline 0.1 m) in 2 runs (the first at "
                       "record 3: 640x480";
        EXPECT_EQ(app.camera_change.rfind(end, 0), 0U) << app.camera_change;
        EXPECT_NE(err.find("emslam-odometry: warning: " + end), std::string::npos) << err;
        expectStrictlyIncreasing(out, app.frames_processed);
    }
}
