// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/TrajectoryReader.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

using emslam::io::loadTrajectory;
using emslam::io::TrajectoryFormat;
using emslam::io::TrajectoryReadOptions;
using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

namespace
{
const char* const KITTI_TWO_POSES = "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0.5 0 1 0 0 0 0 1 2\n";
}

TEST(TrajectoryReader, readsEachFormatTheSame)
{
    const std::string dir = emslam::test::makeTempDir("traj_reader");
    writeFile(dir + "/t.tum", "1700000000.0 0 0 0 0 0 0 1\n1700000000.1 0.5 0 2 0 0 0 1\n");
    writeFile(dir + "/t_kitti.txt", KITTI_TWO_POSES);
    writeFile(dir + "/t_times.txt", "1700000000.0\n1700000000.1\n");
    writeFile(
        dir + "/t.csv", "1700000000000000000,0,0,0,0,0,0,1\n1700000000100000000,0.5,0,2,0,0,0,1\n");
    for (const char* f : {"/t.tum", "/t_kitti.txt", "/t.csv"})
    {
        SCOPED_TRACE(f);
        const auto r = loadTrajectory(dir + f);
        EXPECT_TRUE(r.timed);
        ASSERT_EQ(r.trajectory.size(), 2U);
        EXPECT_NEAR(r.trajectory.poses[1].t, 1700000000.1, 1e-6);
        EXPECT_DOUBLE_EQ(r.trajectory.poses[1].pose.x(), 0.5);
        EXPECT_DOUBLE_EQ(r.trajectory.poses[1].pose.z(), 2.0);
    }
    EXPECT_EQ(loadTrajectory(dir + "/t.csv").format, TrajectoryFormat::Euroc);
    EXPECT_EQ(loadTrajectory(dir + "/t_kitti.txt").times_file, dir + "/t_times.txt");
}

TEST(TrajectoryReader, kittiWithoutTimesIsReadByIndexAndSaysWhatIsMissing)
{
    const std::string dir = emslam::test::makeTempDir("traj_reader_untimed");
    writeFile(dir + "/poses.txt", KITTI_TWO_POSES);
    const auto r = loadTrajectory(dir + "/poses.txt");
    EXPECT_EQ(r.format, TrajectoryFormat::Kitti);
    EXPECT_FALSE(r.timed);
    ASSERT_EQ(r.trajectory.size(), 2U);
    EXPECT_EQ(r.trajectory.poses[1].t, 1.0);
    const std::string msg = r.missingTimesMessage(dir + "/poses.txt");
    EXPECT_NE(msg.find("poses.txt' has no times file"), std::string::npos) << msg;
    EXPECT_NE(msg.find(dir + "/poses_times.txt"), std::string::npos) << msg;
    EXPECT_NE(msg.find(dir + "/times.txt"), std::string::npos) << msg;

    // Given explicitly, with sequence times: the KITTI offset is added.
    writeFile(dir + "/seq_times.txt", "0.0\n0.1\n");
    TrajectoryReadOptions o;
    o.times_file = dir + "/seq_times.txt";
    o.kitti_time_offset = 1000.0;
    const auto timed = loadTrajectory(dir + "/poses.txt", o);
    EXPECT_TRUE(timed.timed);
    EXPECT_DOUBLE_EQ(timed.trajectory.poses[1].t, 1000.1);
}

TEST(TrajectoryReader, aForcedFormatThatDoesNotFitFails)
{
    const std::string dir = emslam::test::makeTempDir("traj_reader_forced");
    writeFile(dir + "/k.txt", KITTI_TWO_POSES);
    TrajectoryReadOptions o;
    o.format = TrajectoryFormat::Tum;
    expectThrowContaining([&] { loadTrajectory(dir + "/k.txt", o); }, {"k.txt:1", "8 numbers"});
    o.format = TrajectoryFormat::Euroc;
    expectThrowContaining([&] { loadTrajectory(dir + "/k.txt", o); }, {"k.txt:1"});
}

// poses/06.txt as KITTI lays it out: times found in sequences/06, UNIX times
// as emslam-import kitti gives the observations.
TEST(TrajectoryReader, readsKitti06WithItsTimes)
{
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    const auto r = loadTrajectory(poses);
    EXPECT_EQ(r.format, TrajectoryFormat::Kitti);
    ASSERT_TRUE(r.timed);
    ASSERT_EQ(r.trajectory.size(), 51U);
    EXPECT_DOUBLE_EQ(r.trajectory.poses[0].t, emslam::io::KittiSequence::DEFAULT_TIME_OFFSET);
    EXPECT_NEAR(
        r.trajectory.poses[1].t, emslam::io::KittiSequence::DEFAULT_TIME_OFFSET + 0.1044989, 1e-6);
}
