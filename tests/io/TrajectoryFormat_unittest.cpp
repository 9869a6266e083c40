// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/TrajectoryFormat.h>

#include <gtest/gtest.h>

#include <string>

using emslam::io::detectTrajectoryFormat;
using emslam::io::TrajectoryFormat;
using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

TEST(TrajectoryFormat, namesParseBack)
{
    for (const auto f :
         {TrajectoryFormat::Auto, TrajectoryFormat::Tum, TrajectoryFormat::Kitti,
          TrajectoryFormat::Euroc})
    {
        EXPECT_EQ(emslam::io::parseTrajectoryFormat(emslam::io::trajectoryFormatName(f)), f);
    }
    EXPECT_EQ(emslam::io::parseTrajectoryFormat("KITTI"), TrajectoryFormat::Kitti);
    expectThrowContaining(
        [] { emslam::io::parseTrajectoryFormat("csv"); }, {"'csv'", "tum, kitti or euroc"});
}

TEST(TrajectoryFormat, toldFromTheFirstDataLine)
{
    const std::string dir = emslam::test::makeTempDir("traj_format");
    writeFile(dir + "/a.tum", "# comment\n\n1700000000.000000000 1 2 3 0 0 0 1\n");
    writeFile(dir + "/b.txt", "1.000000e+00 0 0 0 0 1.000000e+00 0 0 0 0 1 2.220446e-16\n");
    writeFile(
        dir + "/c.csv", "1403715274312143104.0000000000,0.86,2.20,0.92,0.42,0.62,-0.54,0.36\n");
    writeFile(
        dir + "/d.csv",
        "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
        "q_RS_z []\n1403715273262142976,0.87,2.14,0.94,0.06,-0.82,-0.05,-0.55\n");
    writeFile(dir + "/e.tum", "1700000000.5,1,2,3,0,0,0,1\n");  // TUM with commas
    EXPECT_EQ(detectTrajectoryFormat(dir + "/a.tum"), TrajectoryFormat::Tum);
    EXPECT_EQ(detectTrajectoryFormat(dir + "/b.txt"), TrajectoryFormat::Kitti);
    EXPECT_EQ(detectTrajectoryFormat(dir + "/c.csv"), TrajectoryFormat::Euroc);
    EXPECT_EQ(detectTrajectoryFormat(dir + "/d.csv"), TrajectoryFormat::Euroc);
    EXPECT_EQ(detectTrajectoryFormat(dir + "/e.tum"), TrajectoryFormat::Tum);
}

TEST(TrajectoryFormat, unknownContentNamesFileAndLine)
{
    const std::string dir = emslam::test::makeTempDir("traj_format_bad");
    writeFile(dir + "/seven.txt", "# header\n1 2 3 4 5 6 7\n");
    expectThrowContaining(
        [&] { detectTrajectoryFormat(dir + "/seven.txt"); },
        {"seven.txt:2", "cannot tell", "8 numbers (TUM", "12 numbers (KITTI", "EuRoC"});
    writeFile(dir + "/words.txt", "timestamp x y z\n");
    expectThrowContaining([&] { detectTrajectoryFormat(dir + "/words.txt"); }, {"words.txt:1"});
    writeFile(dir + "/empty.txt", "# nothing\n\n");
    expectThrowContaining(
        [&] { detectTrajectoryFormat(dir + "/empty.txt"); }, {"empty.txt", "no pose"});
    expectThrowContaining(
        [&] { detectTrajectoryFormat(dir + "/missing.txt"); }, {"Cannot open", "missing.txt"});
}

// The real files are told apart: KITTI 06 poses, EuRoC camera poses.
TEST(TrajectoryFormat, detectsTheRealGroundTruthFiles)
{
    EMSLAM_REQUIRE_TEST_DATA(kitti, "kitti-odometry/poses/06.txt");
    EMSLAM_REQUIRE_TEST_DATA(euroc, "euroc-v101-rest/groundtruth_left_cam.csv");
    EXPECT_EQ(detectTrajectoryFormat(kitti), TrajectoryFormat::Kitti);
    EXPECT_EQ(detectTrajectoryFormat(euroc), TrajectoryFormat::Euroc);
}
