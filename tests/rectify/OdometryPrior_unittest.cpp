// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/OdometryPrior.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

using emslam::rectify::OdometryPrior;
using mrpt::poses::CPose3D;

TEST(OdometryPrior, isOffByDefaultAndZeroAtTheReference)
{
    const CPose3D ref(0.1, 0.0, 0.3, mrpt::DEG2RAD(4.0), 0, 0);
    EXPECT_FALSE(OdometryPrior{}.enabled());
    EXPECT_EQ(OdometryPrior{}.cost(CPose3D(1, 2, 3, 0, 0, 0), ref, 1), 0.0);
    const OdometryPrior p{2.0, 0.02, 0.5};
    EXPECT_NEAR(p.cost(ref, ref, 1), 0.0, 1e-20);
}

TEST(OdometryPrior, isHalfTheWeightedMahalanobisDistanceOfTheDifference)
{
    const OdometryPrior p{2.0, 0.02, 0.5};
    const CPose3D ref(0.1, 0.0, 0.3, mrpt::DEG2RAD(30.0), 0, 0);
    // 0.03 m along the reference's own x axis: (0.03 / 0.02)^2 = 2.25.
    const CPose3D shifted = ref + CPose3D(0.03, 0, 0, 0, 0, 0);
    EXPECT_NEAR(p.cost(shifted, ref, 1), 0.5 * 2.0 * 2.25, 1e-9);
    // 1 degree more about y: (1 / 0.5)^2 = 4.
    const CPose3D turned = ref + CPose3D(0, 0, 0, 0, mrpt::DEG2RAD(1.0), 0);
    EXPECT_NEAR(p.cost(turned, ref, 1), 0.5 * 2.0 * 4.0, 1e-9);
    // Both, over 4 accepted steps: the variance grows with the steps.
    const CPose3D both = ref + CPose3D(0.03, 0, 0, 0, mrpt::DEG2RAD(1.0), 0);
    EXPECT_NEAR(p.cost(both, ref, 4), 0.5 * 2.0 * (2.25 + 4.0) / 4.0, 1e-9);
    // A tiny angle keeps its precision (acos near 1 would lose it all).
    const CPose3D tiny = ref + CPose3D(0, 0, 0, 1e-7, 0, 0);
    const double expected = mrpt::square(1e-7 / mrpt::DEG2RAD(0.5));
    EXPECT_NEAR(p.cost(tiny, ref, 1), expected, 1e-6 * expected);
}
