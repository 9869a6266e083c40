// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/SpaceSampler.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <TestHelpers.h>

using emslam::rectify::SpaceSampler;
using mrpt::poses::CPose3D;

TEST(SpaceSampler, acceptsWhenTheMotionSinceTheLastAcceptedFrameIsLargeEnough)
{
    SpaceSampler s;                                  // t_min 0.15 m, θ_min 5°
    EXPECT_TRUE(s.feed(CPose3D(5, 5, 5, 0, 0, 0)));  // the first frame, whatever its action
    const CPose3D step(0.0, 0.0, 0.06, 0, 0, 0);
    EXPECT_FALSE(s.feed(step));  // 0.06
    EXPECT_FALSE(s.feed(step));  // 0.12
    EXPECT_TRUE(s.feed(step));   // 0.18 > 0.15
    EXPECT_NEAR(s.actionSinceAccepted().z(), 0.18, 1e-12);
    EXPECT_FALSE(s.feed(step));  // restarts from the accepted frame
    // A turn on the spot: 2° per frame, accepted at 6° > 5°.
    SpaceSampler turn;
    turn.feed(CPose3D());
    const CPose3D yaw(0, 0, 0, 0, mrpt::DEG2RAD(2.0), 0);
    EXPECT_FALSE(turn.feed(yaw));
    EXPECT_FALSE(turn.feed(yaw));
    EXPECT_TRUE(turn.feed(yaw));
    EXPECT_EQ(turn.accepted(), 2u);
    EXPECT_EQ(turn.rejected(), 2u);
}

TEST(SpaceSampler, disabledAcceptsEverythingAndBadValuesThrow)
{
    SpaceSampler::TParameters p;
    p.enabled = false;
    SpaceSampler s(p);
    s.feed(CPose3D());
    EXPECT_TRUE(s.feed(CPose3D()));

    mrpt::config::CConfigFileMemory c("[SpaceSampler]\nt_min = -1\n");
    SpaceSampler::TParameters bad;
    emslam::test::expectThrowContaining(
        [&] { bad.loadFromConfigFile(c, "SpaceSampler"); }, {"[SpaceSampler] t_min"});
}
