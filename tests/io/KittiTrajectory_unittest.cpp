// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/KittiSequence.h>
#include <emslam/io/KittiTrajectory.h>

#include <mrpt/poses/CPose3D.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using emslam::io::KittiTrajectory;
using emslam::io::TumTrajectory;
using emslam::test::expectThrowContaining;
using emslam::test::maxPoseDifference;
using emslam::test::writeFile;
using mrpt::poses::CPose3D;

namespace
{
std::vector<std::string> readLines(const std::string& file)
{
    std::ifstream f(file);
    std::vector<std::string> out;
    for (std::string l; std::getline(f, l);)
    {
        out.push_back(l);
    }
    return out;
}

TumTrajectory sampleTrajectory()
{
    TumTrajectory t;
    // UNIX times with nanoseconds, as imported KITTI / simulated frames carry.
    t.add(1317384506.405868053, CPose3D());
    t.add(1700000000.0, CPose3D(1.5, -0.25, 12.0, 0.3, -0.1, 0.05));
    t.add(1700000000.1, CPose3D(-3.0, 0.001, 1e-7, -2.0, 0.4, 1.0));
    return t;
}
}  // namespace

TEST(KittiTrajectory, writeReadRoundTripWithNanosecondTimes)
{
    const std::string dir = emslam::test::makeTempDir("kitti_traj");
    const auto t = sampleTrajectory();
    const std::string poses = dir + "/traj_kitti.txt";
    const std::string times = KittiTrajectory::timesFileFor(poses);
    EXPECT_EQ(times, dir + "/traj_times.txt");
    KittiTrajectory::save(t, poses, times);

    const auto pose_lines = readLines(poses);
    const auto time_lines = readLines(times);
    ASSERT_EQ(pose_lines.size(), 3U);
    ASSERT_EQ(time_lines.size(), 3U);
    EXPECT_EQ(pose_lines[0], "1 0 0 0 0 1 0 0 0 0 1 0");
    // Fixed point, nanoseconds, never exponent notation.
    EXPECT_EQ(time_lines[0], "1317384506.405868000");
    EXPECT_EQ(time_lines[1], "1700000000.000000000");
    for (const auto& l : pose_lines)
    {
        EXPECT_EQ(l.find('e'), std::string::npos) << l;
    }

    const auto back = KittiTrajectory::load(poses, times, 0.0);
    ASSERT_EQ(back.size(), t.size());
    for (std::size_t i = 0; i < t.size(); i++)
    {
        EXPECT_NEAR(back.poses[i].t, t.poses[i].t, 1e-9) << i;
        EXPECT_LT(maxPoseDifference(back.poses[i].pose, t.poses[i].pose), 1e-12) << i;
    }
}

TEST(KittiTrajectory, rowMajorMatrixOfThePose)
{
    // 90 deg about z, then t = (1, 2, 3): rows [0 -1 0 1], [1 0 0 2], [0 0 1 3].
    const CPose3D T(1, 2, 3, M_PI / 2, 0, 0);
    std::vector<double> v;
    std::istringstream in(KittiTrajectory::formatLine(T));
    for (double x; in >> x;)
    {
        v.push_back(x);
    }
    ASSERT_EQ(v.size(), 12U);
    const std::vector<double> expected = {0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3};
    for (std::size_t i = 0; i < 12; i++)
    {
        EXPECT_NEAR(v[i], expected[i], 1e-15) << i;
    }
}

TEST(KittiTrajectory, sequenceTimesGetTheOffsetUnixTimesDoNot)
{
    const std::string dir = emslam::test::makeTempDir("kitti_traj_offset");
    writeFile(dir + "/p.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1\n");
    writeFile(dir + "/rel.txt", "0.000000e+00\n1.044989e-01\n");
    writeFile(dir + "/abs.txt", "1317340800.0\n1317340800.1044989\n");
    const auto rel = KittiTrajectory::load(dir + "/p.txt", dir + "/rel.txt", 1317340800.0);
    const auto abs = KittiTrajectory::load(dir + "/p.txt", dir + "/abs.txt", 1317340800.0);
    ASSERT_EQ(rel.size(), 2U);
    EXPECT_DOUBLE_EQ(rel.poses[1].t, 1317340800.0 + 0.1044989);
    EXPECT_DOUBLE_EQ(abs.poses[1].t, 1317340800.1044989);
    EXPECT_DOUBLE_EQ(rel.poses[1].pose.z(), 1.0);
}

TEST(KittiTrajectory, findsTheTimesFileOfTheKittiLayout)
{
    const std::string root = emslam::test::makeTempDir("kitti_traj_layout");
    std::filesystem::create_directories(root + "/poses");
    std::filesystem::create_directories(root + "/sequences/06");
    writeFile(root + "/poses/06.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n");
    EXPECT_EQ(KittiTrajectory::findTimesFile(root + "/poses/06.txt"), "");
    const auto candidates = KittiTrajectory::timesFileCandidates(root + "/poses/06.txt");
    ASSERT_EQ(candidates.size(), 3U);
    EXPECT_EQ(candidates[1], root + "/sequences/06/times.txt");
    writeFile(root + "/sequences/06/times.txt", "0.0\n");
    EXPECT_EQ(KittiTrajectory::findTimesFile(root + "/poses/06.txt"), candidates[1]);
    // The times file written beside the poses wins.
    writeFile(root + "/poses/06_times.txt", "0.0\n");
    EXPECT_EQ(KittiTrajectory::findTimesFile(root + "/poses/06.txt"), root + "/poses/06_times.txt");
}

TEST(KittiTrajectory, badContentNamesFileAndLine)
{
    const std::string dir = emslam::test::makeTempDir("kitti_traj_bad");
    writeFile(dir + "/short.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0\n");
    expectThrowContaining(
        [&] { KittiTrajectory::readPoses(dir + "/short.txt"); }, {"short.txt:2", "12 numbers"});
    writeFile(dir + "/skew.txt", "1 0 0 0 0 2 0 0 0 0 1 0\n");
    expectThrowContaining(
        [&] { KittiTrajectory::readPoses(dir + "/skew.txt"); }, {"skew.txt:1", "rotation"});
    writeFile(dir + "/empty.txt", "\n");
    expectThrowContaining([&] { KittiTrajectory::readPoses(dir + "/empty.txt"); }, {"no pose"});
    writeFile(dir + "/p.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 0\n");
    writeFile(dir + "/t.txt", "0.0\n");
    expectThrowContaining(
        [&] { KittiTrajectory::load(dir + "/p.txt", dir + "/t.txt", 0.0); },
        {"p.txt", "2 poses", "t.txt", "1 timestamps"});
    writeFile(dir + "/t2.txt", "0.0\n-1\n");
    expectThrowContaining([&] { KittiTrajectory::readTimes(dir + "/t2.txt"); }, {"t2.txt:2"});
    expectThrowContaining(
        [&] { KittiTrajectory::readTimes(dir + "/none.txt"); }, {"Cannot open", "none.txt"});
}

// The real KITTI 06 excerpt: the ground truth and times.txt, as KittiSequence reads them.
TEST(KittiTrajectory, readsKitti06PosesAndTimes)
{
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    EMSLAM_REQUIRE_TEST_DATA(seq, "kitti-odometry/sequences/06");
    const std::string times = KittiTrajectory::findTimesFile(poses);
    EXPECT_EQ(std::filesystem::canonical(times), std::filesystem::canonical(seq + "/times.txt"));
    const double offset = emslam::io::KittiSequence::DEFAULT_TIME_OFFSET;
    const auto t = KittiTrajectory::load(poses, times, offset);
    const emslam::io::KittiSequence s(seq, poses);
    ASSERT_EQ(t.size(), 51U);
    ASSERT_EQ(s.size(), 51U);
    for (std::size_t i = 0; i < s.size(); i++)
    {
        EXPECT_DOUBLE_EQ(t.poses[i].t, s.timestamp(i)) << i;
        EXPECT_LT(maxPoseDifference(t.poses[i].pose, s.groundTruth(i)), 1e-12) << i;
    }
    EXPECT_NEAR(t.poses[1].pose.z(), 1.198998, 1e-6);  // line 2 of poses/06.txt
}
