// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/EurocTrajectory.h>

#include <mrpt/math/CQuaternion.h>
#include <mrpt/poses/CPose3D.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using emslam::io::EurocTrajectory;
using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

namespace
{
/** The rotation of a pose as a quaternion (w >= 0). */
mrpt::math::CQuaternionDouble quaternionOf(const mrpt::poses::CPose3D& p)
{
    mrpt::math::CQuaternionDouble q;
    p.getAsQuaternion(q);
    q.ensurePositiveRealPart();
    return q;
}
}  // namespace

// EuRoC's state_groundtruth_estimate0/data.csv: header, 17 columns, w first.
TEST(EurocTrajectory, stateGroundTruthHasTheQuaternionWFirst)
{
    const std::string dir = emslam::test::makeTempDir("euroc_traj_state");
    writeFile(
        dir + "/data.csv",
        "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
        "q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x "
        "[rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], "
        "b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n"
        "1403715273262142976,0.878612,2.142470,0.947262,0.060514,-0.828459,-0.058956,-0.553641,"
        "0.009474,-0.014009,-0.003428,-0.002229,0.020700,0.076350,-0.012492,0.547666,0.069073\n"
        "1403715273267142912,0.878658,2.142404,0.947234,0.060476,-0.828449,-0.058923,-0.553664,"
        "0.009203,-0.013900,-0.003325,-0.002229,0.020700,0.076350,-0.012492,0.547666,0.069073\n");
    const auto t = EurocTrajectory::load(dir + "/data.csv");
    ASSERT_EQ(t.size(), 2U);
    EXPECT_NEAR(t.poses[0].t, 1403715273.262142976, 1e-6);
    EXPECT_NEAR(t.poses[1].t - t.poses[0].t, 0.004999936, 1e-6);
    EXPECT_DOUBLE_EQ(t.poses[0].pose.x(), 0.878612);
    EXPECT_DOUBLE_EQ(t.poses[0].pose.z(), 0.947262);
    const auto q = quaternionOf(t.poses[0].pose);
    const double n = std::sqrt(
        0.060514 * 0.060514 + 0.828459 * 0.828459 + 0.058956 * 0.058956 + 0.553641 * 0.553641);
    EXPECT_NEAR(q.r(), 0.060514 / n, 1e-9);
    EXPECT_NEAR(q.x(), -0.828459 / n, 1e-9);
    EXPECT_NEAR(q.y(), -0.058956 / n, 1e-9);
    EXPECT_NEAR(q.z(), -0.553641 / n, 1e-9);
}

// The camera-pose form, without a header: 8 columns, w last.
TEST(EurocTrajectory, cameraPoseFileHasTheQuaternionWLast)
{
    const std::string dir = emslam::test::makeTempDir("euroc_traj_cam");
    writeFile(dir + "/gt.csv", "1403715274312143104.0000000000,1,2,3,0,0,0.6,0.8\n");
    const auto t = EurocTrajectory::load(dir + "/gt.csv");
    ASSERT_EQ(t.size(), 1U);
    const auto q = quaternionOf(t.poses[0].pose);
    EXPECT_NEAR(q.r(), 0.8, 1e-12);
    EXPECT_NEAR(q.z(), 0.6, 1e-12);
    EXPECT_DOUBLE_EQ(t.poses[0].pose.y(), 2.0);
    EXPECT_NEAR(t.poses[0].t, 1403715274.312143104, 1e-6);
    // A header naming qw first decides, whatever the column count.
    writeFile(
        dir + "/w_first.csv", "#t,x,y,z,qw,qx,qy,qz\n1403715274312143104,1,2,3,0.8,0,0,0.6\n");
    const auto w = EurocTrajectory::load(dir + "/w_first.csv");
    EXPECT_NEAR(quaternionOf(w.poses[0].pose).r(), 0.8, 1e-12);
    EXPECT_NEAR(quaternionOf(w.poses[0].pose).z(), 0.6, 1e-12);
}

TEST(EurocTrajectory, badRowsNameFileAndLine)
{
    const std::string dir = emslam::test::makeTempDir("euroc_traj_bad");
    writeFile(dir + "/few.csv", "1403715274312143104,1,2,3,0,0,0,1\n1403715274362142976,1,2\n");
    expectThrowContaining([&] { EurocTrajectory::load(dir + "/few.csv"); }, {"few.csv:2", "8"});
    writeFile(dir + "/nan.csv", "1403715274312143104,1,x,3,0,0,0,1\n");
    expectThrowContaining(
        [&] { EurocTrajectory::load(dir + "/nan.csv"); }, {"nan.csv:1", "not a number"});
    writeFile(dir + "/zero.csv", "1403715274312143104,1,2,3,0,0,0,0\n");
    expectThrowContaining(
        [&] { EurocTrajectory::load(dir + "/zero.csv"); }, {"zero.csv:1", "zero quaternion"});
    writeFile(dir + "/header_only.csv", "#timestamp,x,y,z,qx,qy,qz,qw\n");
    expectThrowContaining(
        [&] { EurocTrajectory::load(dir + "/header_only.csv"); }, {"header_only.csv", "no pose"});
}

// Stamps outside [0, INT64_MAX] ns are refused (INT64_MIN made differences overflow).
TEST(EurocTrajectory, timestampsOutsideTheNanosecondRangeAreRefused)
{
    const std::string dir = emslam::test::makeTempDir("euroc_traj_int64");
    for (const std::string bad : {"-9223372036854775808", "-5", "9223372036854775808"})
    {
        writeFile(dir + "/t.csv", "0,1,2,3,0,0,0,1\n" + bad + ",1,2,3,0,0,0,1\n");
        expectThrowContaining(
            [&] { EurocTrajectory::load(dir + "/t.csv"); },
            {"t.csv:2", "'" + bad + "'", "nanoseconds"});
    }
    writeFile(dir + "/max.csv", "9223372036854775807,1,2,3,0,0,0,1\n");
    const auto t = EurocTrajectory::load(dir + "/max.csv");
    ASSERT_EQ(t.size(), 1U);
    EXPECT_NEAR(t.poses[0].t, 9223372036.854775807, 1e-5);
}

// The real V1_01_easy excerpt: the left camera's poses (8 columns, w last).
TEST(EurocTrajectory, readsTheEurocExcerpt)
{
    EMSLAM_REQUIRE_TEST_DATA(file, "euroc-v101-rest/groundtruth_left_cam.csv");
    const auto t = EurocTrajectory::load(file);
    ASSERT_GE(t.size(), 40U);
    // First row: 1403715274312143104,0.8687393558,2.2070275302,0.9257726725,
    // 0.4259596512,0.6262011737,-0.5441421096,0.361026079545
    EXPECT_NEAR(t.poses[0].t, 1403715274.312143104, 1e-6);
    EXPECT_DOUBLE_EQ(t.poses[0].pose.x(), 0.8687393558);
    const auto q = quaternionOf(t.poses[0].pose);
    EXPECT_NEAR(q.r(), 0.361026079545, 1e-9);
    EXPECT_NEAR(q.x(), 0.4259596512, 1e-9);
    // At rest: under 3 mm of motion over the excerpt.
    const auto& p0 = t.poses.front().pose;
    const auto& p1 = t.poses.back().pose;
    const double d = std::hypot(p1.x() - p0.x(), p1.y() - p0.y(), p1.z() - p0.z());
    EXPECT_LT(d, 0.003);
}
