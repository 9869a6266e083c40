// SPDX-License-Identifier: BSD-3-Clause
// meanPose(): the mean of poses found by independent rectifications.
#include <emslam/rectify/PoseMean.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/math/CQuaternion.h>

#include <gtest/gtest.h>

#include <stdexcept>

using emslam::rectify::meanPose;
using mrpt::DEG2RAD;
using mrpt::poses::CPose3D;

TEST(PoseMean, symmetricSpreadAveragesToItsCentre)
{
    const CPose3D centre(1.0, -2.0, 3.0, DEG2RAD(30.0), DEG2RAD(-10.0), DEG2RAD(5.0));
    // Opposite translations and opposite rotations about the centre.
    const CPose3D t(0.2, 0.3, -0.1, 0, 0, 0);
    const CPose3D r(0, 0, 0, DEG2RAD(2.0), DEG2RAD(-3.0), DEG2RAD(1.0));
    const CPose3D m =
        meanPose({centre + t, centre + (CPose3D() - t), centre + r, centre + (CPose3D() - r)});
    EXPECT_NEAR(m.x(), centre.x(), 1e-12);
    EXPECT_NEAR(m.y(), centre.y(), 1e-12);
    EXPECT_NEAR(m.z(), centre.z(), 1e-12);
    // q and its inverse sum to the identity's direction: exact.
    const CPose3D d = m - centre;
    EXPECT_NEAR(d.yaw(), 0.0, 1e-12);
    EXPECT_NEAR(d.pitch(), 0.0, 1e-12);
    EXPECT_NEAR(d.roll(), 0.0, 1e-12);
}

TEST(PoseMean, translationsAreAveragedExactly)
{
    const CPose3D m = meanPose(
        {CPose3D(0, 0, 0, 0, 0, 0), CPose3D(1, 2, 3, 0, 0, 0), CPose3D(2, -2, 0, 0, 0, 0)});
    EXPECT_DOUBLE_EQ(m.x(), 1.0);
    EXPECT_DOUBLE_EQ(m.y(), 0.0);
    EXPECT_DOUBLE_EQ(m.z(), 1.0);
}

TEST(PoseMean, yawOnlyPosesGiveAYawOnlyMean)
{
    // 3DOF trajectories (rotation about the camera's y axis) stay 3DOF.
    const CPose3D m = meanPose(
        {CPose3D(0, 0, 0, 0, DEG2RAD(10.0), 0), CPose3D(0, 0, 0, 0, DEG2RAD(20.0), 0),
         CPose3D(0, 0, 0, 0, DEG2RAD(36.0), 0)});
    EXPECT_NEAR(m.pitch(), DEG2RAD(22.0), DEG2RAD(0.05));
    EXPECT_NEAR(m.yaw(), 0.0, 1e-12);
    EXPECT_NEAR(m.roll(), 0.0, 1e-12);
}

TEST(PoseMean, oppositeQuaternionSignsAreTheSameRotation)
{
    // Angles across ±180°: the quaternions can come out with opposite signs;
    // a plain sum would cancel them.
    const CPose3D a(0, 0, 0, DEG2RAD(179.0), 0, 0);
    const CPose3D b(0, 0, 0, DEG2RAD(-179.0), 0, 0);
    const CPose3D m = meanPose({a, b});
    EXPECT_NEAR(std::abs(m.yaw()), DEG2RAD(180.0), DEG2RAD(0.01));
    EXPECT_EQ(meanPose({a}).yaw(), a.yaw());
}

TEST(PoseMean, noPosesIsAnError)
{
    EXPECT_THROW(meanPose({}), std::invalid_argument);
}
