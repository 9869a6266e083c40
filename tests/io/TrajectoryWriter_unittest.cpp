// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/KittiTrajectory.h>
#include <emslam/io/TrajectoryReader.h>
#include <emslam/io/TrajectoryWriter.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

using emslam::io::saveTrajectory;
using emslam::io::TrajectoryOutput;
using emslam::io::TumTrajectory;

namespace
{
TumTrajectory sample()
{
    TumTrajectory t;
    for (int i = 0; i < 5; i++)
    {
        t.add(1700000000.0 + 0.1 * i, mrpt::poses::CPose3D(0.3 * i, 0, 1.0 * i, 0.01 * i, 0, 0));
    }
    return t;
}
}  // namespace

TEST(TrajectoryWriter, writesTheChosenFormatsAndTheyReadBackEqual)
{
    const std::string dir = emslam::test::makeTempDir("traj_writer");
    const auto t = sample();
    EXPECT_EQ(
        saveTrajectory(t, dir + "/a.tum", TrajectoryOutput::Tum),
        std::vector<std::string>{dir + "/a.tum"});
    EXPECT_EQ(
        saveTrajectory(t, dir + "/b_kitti.txt", TrajectoryOutput::Kitti),
        (std::vector<std::string>{dir + "/b_kitti.txt", dir + "/b_times.txt"}));
    EXPECT_EQ(
        saveTrajectory(t, dir + "/c.tum", TrajectoryOutput::Both),
        (std::vector<std::string>{dir + "/c.tum", dir + "/c_kitti.txt", dir + "/c_times.txt"}));
    for (const char* f : {"/a.tum", "/b_kitti.txt", "/c.tum", "/c_kitti.txt"})
    {
        SCOPED_TRACE(f);
        const auto r = emslam::io::loadTrajectory(dir + f);
        ASSERT_TRUE(r.timed);
        ASSERT_EQ(r.trajectory.size(), t.size());
        for (std::size_t i = 0; i < t.size(); i++)
        {
            EXPECT_NEAR(r.trajectory.poses[i].t, t.poses[i].t, 1e-9);
            EXPECT_LT(
                emslam::test::maxPoseDifference(r.trajectory.poses[i].pose, t.poses[i].pose),
                1e-12);
        }
    }
    EXPECT_FALSE(std::filesystem::exists(dir + "/a_kitti.txt"));
    EXPECT_FALSE(std::filesystem::exists(dir + "/b_kitti.tum"));
}

TEST(TrajectoryWriter, outputNamesParse)
{
    EXPECT_EQ(emslam::io::parseTrajectoryOutput("tum"), TrajectoryOutput::Tum);
    EXPECT_EQ(emslam::io::parseTrajectoryOutput("KITTI"), TrajectoryOutput::Kitti);
    EXPECT_EQ(emslam::io::parseTrajectoryOutput("both"), TrajectoryOutput::Both);
    emslam::test::expectThrowContaining(
        [] { emslam::io::parseTrajectoryOutput("euroc"); }, {"'euroc'", "tum, kitti or both"});
    EXPECT_EQ(
        emslam::io::kittiFileBeside("out/trajectory_slam.tum"), "out/trajectory_slam_kitti.txt");
}
