// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/TumTrajectory.h>

#include <mrpt/math/CQuaternion.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/random/RandomGenerators.h>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using emslam::io::TumPose;
using emslam::io::TumTrajectory;

using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

namespace
{
/** Largest absolute difference between the 3x4 matrices of two poses. */
double poseDiff(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
    const auto A = a.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    const auto B = b.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    double m = 0;
    for (int r = 0; r < 3; r++)
    {
        for (int c = 0; c < 4; c++)
        {
            m = std::max(m, std::abs(A(r, c) - B(r, c)));
        }
    }
    return m;
}
}  // namespace

TEST(TumTrajectory, writeReadRoundTrip)
{
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(1234);
    TumTrajectory traj;
    for (int i = 0; i < 200; i++)
    {
        // EuRoC-like UNIX times and KITTI-like small ones, poses anywhere.
        const double t = (i % 2 == 0 ? 1403715274.0 : 0.0) + 0.05 * i + rng.drawUniform(0, 1e-3);
        traj.add(
            t, mrpt::poses::CPose3D(
                   rng.drawUniform(-500, 500), rng.drawUniform(-500, 500), rng.drawUniform(-50, 50),
                   rng.drawUniform(-M_PI, M_PI), rng.drawUniform(-1.5, 1.5),
                   rng.drawUniform(-M_PI, M_PI)));
    }
    traj.add(3.0, mrpt::poses::CPose3D());  // identity
    const std::string file = emslam::test::makeTempDir("tumtraj") + "/t.tum";
    traj.saveToFile(file);
    const auto back = TumTrajectory::fromFile(file);
    ASSERT_EQ(back.size(), traj.size());
    for (std::size_t i = 0; i < traj.size(); i++)
    {
        EXPECT_NEAR(back.poses[i].t, traj.poses[i].t, 1e-9) << i;
        EXPECT_LT(poseDiff(back.poses[i].pose, traj.poses[i].pose), 1e-9) << i;
    }
    // One line per pose, no header.
    std::ifstream f(file);
    std::size_t lines = 0;
    for (std::string l; std::getline(f, l);)
    {
        ++lines;
    }
    EXPECT_EQ(lines, traj.size());
    EXPECT_EQ(TumTrajectory::formatLine(traj.poses.back()), "3.000000000 0 0 0 0 0 0 1");
}

TEST(TumTrajectory, unixTimesAreWrittenFixedPointToTheNanosecond)
{
    // Whole seconds once came out as "1.7e+09", which TUM tools misread.
    EXPECT_EQ(emslam::io::formatTimestamp(1.7e9), "1700000000.000000000");
    EXPECT_EQ(emslam::io::formatTimestamp(1317384506.405868053), "1317384506.405868000");
    // Not the double's binary noise ("1700000000.200000048").
    EXPECT_EQ(emslam::io::formatTimestamp(1.7e9 + 0.2), "1700000000.200000000");
    EXPECT_EQ(emslam::io::formatTimestamp(1.25e-9), "0.000000001");
    EXPECT_EQ(emslam::io::formatTimestamp(0.1), "0.100000000");
    TumTrajectory traj;
    traj.add(1.7e9, mrpt::poses::CPose3D(1e-17, -2.5e-9, 3e20, 0.1, 0.2, 0.3));
    traj.add(1.7e9 + 0.25, mrpt::poses::CPose3D());  // exact in a double
    const std::string file = emslam::test::makeTempDir("tumtraj_fixed") + "/t.tum";
    traj.saveToFile(file);
    std::ifstream f(file);
    std::vector<std::string> lines;
    for (std::string l; std::getline(f, l);)
    {
        EXPECT_EQ(l.find('e'), std::string::npos) << l;
        lines.push_back(l);
    }
    ASSERT_EQ(lines.size(), 2U);
    EXPECT_EQ(lines[0].substr(0, 21), "1700000000.000000000 ");
    EXPECT_EQ(lines[1].substr(0, 21), "1700000000.250000000 ");
    const auto back = TumTrajectory::fromFile(file);
    EXPECT_EQ(back.poses[1].t, 1.7e9 + 0.25);
    EXPECT_DOUBLE_EQ(back.poses[0].pose.x(), 1e-17);  // exact: shortest fixed form
    EXPECT_DOUBLE_EQ(back.poses[0].pose.z(), 3e20);
}

TEST(TumTrajectory, writesTumConventions)
{
    // 180 deg about z (qw = 0), then 90 deg about z, written with qw >= 0.
    const mrpt::math::CQuaternionDouble q(0, 0, 0, 1);
    TumTrajectory traj;
    traj.add(1.5, mrpt::poses::CPose3D(q, 1, 2, 3));
    traj.add(2.5, mrpt::poses::CPose3D(0, 0, 0, M_PI / 2, 0, 0));
    std::ostringstream ss;
    traj.writeTo(ss);
    std::istringstream in(ss.str());
    double v[8];
    for (auto& x : v)
    {
        in >> x;
    }
    EXPECT_EQ(v[0], 1.5);
    EXPECT_EQ(v[1], 1.0);
    EXPECT_EQ(v[3], 3.0);
    EXPECT_NEAR(std::abs(v[6]), 1.0, 1e-12);  // qz
    EXPECT_GE(v[7], 0.0);                     // qw
    for (auto& x : v)
    {
        in >> x;
    }
    EXPECT_NEAR(v[6], std::sqrt(0.5), 1e-12);  // qz
    EXPECT_NEAR(v[7], std::sqrt(0.5), 1e-12);  // qw
}

TEST(TumTrajectory, readsCommentsSeparatorsAndUnnormalizedQuaternions)
{
    const std::string file = emslam::test::makeTempDir("tumtraj_read") + "/gt.txt";
    writeFile(
        file,
        "# ground truth trajectory\n"
        "# timestamp tx ty tz qx qy qz qw\n"
        "\n"
        "1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 -0.3986\r\n"
        "1305031098.6758\t1.3543\t0.6306\t1.6360\t0.6129\t0.5966\t-0.3316\t-0.3980\n"
        "1.0,1,2,3,0,0,0,2\n");
    const auto t = TumTrajectory::fromFile(file);
    ASSERT_EQ(t.size(), 3U);
    EXPECT_DOUBLE_EQ(t.poses[0].t, 1305031098.6659);
    EXPECT_DOUBLE_EQ(t.poses[1].pose.y(), 0.6306);
    EXPECT_LT(poseDiff(t.poses[2].pose, mrpt::poses::CPose3D(1, 2, 3, 0, 0, 0)), 1e-12);
    mrpt::math::CQuaternionDouble q;
    t.poses[0].pose.getAsQuaternion(q);
    EXPECT_NEAR(q.normSqr(), 1.0, 1e-12);
}

TEST(TumTrajectory, badFilesThrow)
{
    const std::string dir = emslam::test::makeTempDir("tumtraj_bad");
    TumTrajectory t;
    expectThrowContaining([&] { t.loadFromFile(dir + "/none.txt"); }, {dir + "/none.txt"});
    writeFile(dir + "/a.txt", "# c\n1 2 3 4 0 0 0 1\n1 2 3 4 0 0 0\n");
    expectThrowContaining([&] { t.loadFromFile(dir + "/a.txt"); }, {dir + "/a.txt:3", "8 numbers"});
    writeFile(dir + "/b.txt", "1 2 3 4 0 0 zero 1\n");
    expectThrowContaining([&] { t.loadFromFile(dir + "/b.txt"); }, {dir + "/b.txt:1"});
    writeFile(dir + "/c.txt", "1 2 3 4 0 0 0 0\n");
    expectThrowContaining([&] { t.loadFromFile(dir + "/c.txt"); }, {"zero quaternion"});
    writeFile(dir + "/d.txt", "1 2 nan 4 0 0 0 1\n");
    expectThrowContaining([&] { t.loadFromFile(dir + "/d.txt"); }, {"non-finite"});
    expectThrowContaining(
        [&] { TumTrajectory().saveToFile(dir + "/no/such/dir/x.tum"); }, {"x.tum"});
}
