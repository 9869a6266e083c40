// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include <emslam/sim/Trajectory.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <cmath>

using emslam::sim::Trajectory;

namespace
{
Trajectory make(const std::string& text)
{
    mrpt::config::CConfigFileMemory c("[Trajectory]\n" + text);
    Trajectory::TParameters p;
    p.loadFromConfigFile(c, "Trajectory");
    Trajectory t;
    t.setup(p);
    return t;
}
}  // namespace

TEST(Trajectory, robot3dofIsPlanarAtCameraHeight)
{
    for (const char* drive : {"differential", "holonomic"})
    {
        const Trajectory t = make(
            std::string("type = robot3dof\nwaypoints = 0 0; 4 0; 4 4\ncamera_height = 1.3\n"
                        "drive = ") +
            drive + "\n");
        const auto T0 = t.cameraPose(0);
        for (double s = 0; s <= t.duration(); s += 0.1)
        {
            const auto T = t.cameraPose(s);
            EXPECT_NEAR(T.y(), 1.3, 1e-12);
            // Relative to the first camera: rotation about the camera's y axis only.
            const auto rel = T - T0;
            EXPECT_NEAR(rel.getRotationMatrix()(1, 1), 1.0, 1e-9) << drive;
            EXPECT_NEAR(rel.y(), 0.0, 1e-9);
        }
        // Camera looks along +Z at the start (the first segment goes +X: yaw 90 deg).
        EXPECT_NEAR(T0.getRotationMatrix()(0, 2), 1.0, 1e-9);
    }
}

TEST(Trajectory, differentialDriveTurnsOnTheSpot)
{
    const Trajectory t =
        make("type = robot3dof\nwaypoints = 0 0; 4 0; 4 4\nspeed = 1\nangular_speed_deg = 90\n");
    // 4 m, a 90 deg turn (1 s), 4 m.
    EXPECT_NEAR(t.duration(), 9.0, 1e-9);
    const auto a = t.cameraPose(4.0);
    const auto b = t.cameraPose(5.0);
    EXPECT_NEAR(a.distanceTo(b), 0.0, 1e-9);
    const auto R = (b - a).getRotationMatrix();
    EXPECT_NEAR(std::acos((R(0, 0) + R(1, 1) + R(2, 2) - 1) / 2), M_PI / 2, 1e-9);
    EXPECT_NEAR(std::abs(R(0, 2)), 1.0, 1e-9);  // about the camera's y axis
}

TEST(Trajectory, closedLoopsReturnToTheStart)
{
    const Trajectory t =
        make("type = robot3dof\nwaypoints = 0 0; 4 0; 4 4; 0 4\nclosed = true\nloops = 2\n");
    const auto d = t.cameraPose(t.duration()) - t.cameraPose(0);
    EXPECT_NEAR(d.norm(), 0.0, 1e-9);
    // Same heading too: the last pose is the first one.
    const auto R = d.getRotationMatrix();
    EXPECT_NEAR(R(0, 0) + R(1, 1) + R(2, 2), 3.0, 1e-9);
    // 8 on-the-spot turns of 90 deg at 30 deg/s: 3 corners per loop, the
    // junction between loops, and the final turn back to the start heading.
    EXPECT_NEAR(t.duration(), 32 / 0.6 + 8 * 3.0, 1e-6);
}

TEST(Trajectory, walkerBobsAndClimbs)
{
    const Trajectory t = make(
        "type = walker6dof\nwaypoints = 0 0 0; 5 0 0; 10 3 0\ncamera_height = 1.6\n"
        "bob_amplitude = 0.05\n");
    double ymin = 1e9;
    double ymax = -1e9;
    double roll_max = 0;
    for (double s = 0; s < 5.0 / 0.6; s += 0.05)
    {
        const auto T = t.cameraPose(s);
        ymin = std::min(ymin, T.y());
        ymax = std::max(ymax, T.y());
        const auto rel = T - t.cameraPose(0);
        roll_max = std::max(roll_max, std::abs(rel.roll()));
    }
    EXPECT_NEAR(ymax - ymin, 0.10, 0.01);
    EXPECT_GT(roll_max, 0.01);
    EXPECT_NEAR(t.cameraPose(t.duration()).y(), 3 + 1.6, 0.06);
}

TEST(Trajectory, closedWalkStartsAndEndsStandingStill)
{
    // A square walked from the middle of a side: the last segment has the
    // first one's heading, and the gait fades in and out, so the last pose is
    // the first one (bobbing, roll and pitch included).
    const Trajectory t = make(
        "type = walker6dof\nwaypoints = 2 0; 4 0; 4 4; 0 4; 0 0\nclosed = true\n"
        "camera_height = 1.6\nbob_amplitude = 0.05\nsway_roll_deg = 3\nsway_pitch_deg = 2\n");
    const auto first = t.cameraPose(0);
    EXPECT_NEAR(first.y(), 1.6, 1e-12);
    EXPECT_NEAR(first.roll(), 0.0, 1e-12);
    const auto d = t.cameraPose(t.duration()) - first;
    EXPECT_NEAR(d.norm(), 0.0, 1e-9);
    const auto R = d.getRotationMatrix();
    EXPECT_NEAR(R(0, 0) + R(1, 1) + R(2, 2), 3.0, 1e-9);
    // In the middle it walks with the full gait.
    double ymin = 1e9;
    double ymax = -1e9;
    for (double s = 0.4 * t.duration(); s < 0.6 * t.duration(); s += 0.02)
    {
        ymin = std::min(ymin, t.cameraPose(s).y());
        ymax = std::max(ymax, t.cameraPose(s).y());
    }
    EXPECT_NEAR(ymax - ymin, 0.10, 0.01);
}

TEST(Trajectory, badParametersNameTheKey)
{
    using emslam::test::expectThrowContaining;
    expectThrowContaining([] { make("waypoints =\n"); }, {"[Trajectory] waypoints", "empty"});
    expectThrowContaining([] { make("waypoints = 1 2\n"); }, {"[Trajectory] waypoints"});
    expectThrowContaining([] { make("waypoints = 1 2; 3\n"); }, {"[Trajectory] waypoints"});
    expectThrowContaining(
        [] { make("type = drone\nwaypoints = 0 0; 1 1\n"); }, {"[Trajectory] type", "drone"});
    expectThrowContaining(
        [] { make("waypoints = 0 0; 1 1\nspeed = -1\n"); }, {"[Trajectory] speed"});
    expectThrowContaining(
        [] { make("waypoints = 0 0; 1 1\nloops = 2\n"); }, {"[Trajectory] loops"});
}

TEST(Trajectory, parametersSaveLoadRoundTrip)
{
    Trajectory::TParameters p;
    p.type = "walker6dof";
    p.waypoints = "1 0 2; 3 1 4";
    p.closed = true;
    p.loops = 3;
    p.speed = 0.9;
    p.follow_ground = true;
    mrpt::config::CConfigFileMemory c;
    p.saveToConfigFile(c, "Trajectory");
    mrpt::config::CConfigFileMemory r(c.getContent());
    Trajectory::TParameters q;
    q.loadFromConfigFile(r, "Trajectory");
    EXPECT_EQ(q.type, p.type);
    EXPECT_EQ(q.waypoints, p.waypoints);
    EXPECT_EQ(q.closed, true);
    EXPECT_EQ(q.loops, 3);
    EXPECT_EQ(q.speed, 0.9);
    EXPECT_EQ(q.follow_ground, true);
}
