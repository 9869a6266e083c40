// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/ActionCovariance.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <random>

using emslam::rectify::ActionCovariance;
using emslam::rectify::ActionDelta;
using mrpt::poses::CPose3D;

namespace
{
ActionCovariance diag(const std::array<double, 6>& sd)
{
    ActionCovariance c;
    c.setZero();
    for (int k = 0; k < 6; ++k)
    {
        c(k, k) = sd[static_cast<std::size_t>(k)] * sd[static_cast<std::size_t>(k)];
    }
    return c;
}

/** A draw of N(0, c) for a diagonal c. */
ActionDelta drawDiagonal(const ActionCovariance& c, std::mt19937& rng)
{
    std::normal_distribution<double> n(0.0, 1.0);
    ActionDelta d{};
    for (int k = 0; k < 6; ++k)
    {
        d[static_cast<std::size_t>(k)] = std::sqrt(c(k, k)) * n(rng);
    }
    return d;
}
}  // namespace

TEST(ActionCovariance, differenceInvertsThePerturbation)
{
    const CPose3D a(0.4, -0.1, 1.3, mrpt::DEG2RAD(20), mrpt::DEG2RAD(-5), mrpt::DEG2RAD(3));
    const ActionDelta d{0.01, -0.02, 0.03, 0.002, -0.004, 0.001};
    const ActionDelta back =
        emslam::rectify::actionDifference(emslam::rectify::perturbAction(a, d), a);
    for (std::size_t k = 0; k < 6; ++k)
    {
        EXPECT_NEAR(back[k], d[k], 1e-12) << k;
    }
}

TEST(ActionCovariance, compositionMatchesMonteCarlo)
{
    // a1 ⊕ a2 with both perturbed: the sample covariance of the composed
    // action's difference must match the first-order propagation.
    const CPose3D a1(0.5, 0.05, 1.0, mrpt::DEG2RAD(30), mrpt::DEG2RAD(4), mrpt::DEG2RAD(-2));
    const CPose3D a2(-0.2, 0.0, 1.5, mrpt::DEG2RAD(-10), 0, mrpt::DEG2RAD(1));
    const ActionCovariance c1 = diag({0.01, 0.02, 0.005, 0.002, 0.003, 0.001});
    const ActionCovariance c2 = diag({0.02, 0.01, 0.01, 0.001, 0.002, 0.004});
    const ActionCovariance predicted = emslam::rectify::composeCovariance(a1, c1, a2, c2);

    std::mt19937 rng(5);
    const CPose3D a = a1 + a2;
    const int n = 40000;
    ActionCovariance sample;
    sample.setZero();
    for (int i = 0; i < n; ++i)
    {
        const CPose3D p1 = emslam::rectify::perturbAction(a1, drawDiagonal(c1, rng));
        const CPose3D p2 = emslam::rectify::perturbAction(a2, drawDiagonal(c2, rng));
        const ActionDelta d = emslam::rectify::actionDifference(p1 + p2, a);
        for (int r = 0; r < 6; ++r)
        {
            for (int c = 0; c < 6; ++c)
            {
                sample(r, c) += d[static_cast<std::size_t>(r)] * d[static_cast<std::size_t>(c)] / n;
            }
        }
    }
    for (int r = 0; r < 6; ++r)
    {
        // 40,000 draws: ~1 % sampling error on a variance; second-order terms
        // of these small deviations stay below a few %.
        EXPECT_NEAR(sample(r, r), predicted(r, r), 0.05 * predicted(r, r)) << r;
        for (int c = 0; c < r; ++c)
        {
            const double scale = std::sqrt(predicted(r, r) * predicted(c, c));
            EXPECT_NEAR(sample(r, c), predicted(r, c), 0.05 * scale) << r << "," << c;
        }
    }
}

TEST(ActionCovariance, transportRotatesOnlyTheTranslation)
{
    const CPose3D fixed(1, 2, 3, mrpt::DEG2RAD(90), 0, 0);  // yaw 90°: x -> y
    const ActionCovariance c = diag({0.1, 0.01, 0.02, 0.003, 0.004, 0.005});
    const ActionCovariance t = emslam::rectify::transportCovariance(fixed, c);
    EXPECT_NEAR(t(0, 0), 0.01 * 0.01, 1e-12);
    EXPECT_NEAR(t(1, 1), 0.1 * 0.1, 1e-12);
    EXPECT_NEAR(t(2, 2), 0.02 * 0.02, 1e-12);
    for (int k = 3; k < 6; ++k)
    {
        EXPECT_NEAR(t(k, k), c(k, k), 1e-15);
    }
}

TEST(ActionCovariance, informationOfThePlanarComponents)
{
    const ActionCovariance c = diag({0.1, 0.2, 0.4, 0.01, 0.02, 0.04});
    const ActionCovariance i3 = emslam::rectify::informationOf(c, 3);
    EXPECT_NEAR(i3(0, 0), 100.0, 1e-9);
    EXPECT_NEAR(i3(2, 2), 1.0 / 0.16, 1e-9);
    EXPECT_NEAR(i3(4, 4), 1.0 / 0.0004, 1e-6);
    EXPECT_EQ(i3(1, 1), 0.0);  // δy, δθx, δθz carry no information in 3DOF
    EXPECT_EQ(i3(3, 3), 0.0);
    EXPECT_EQ(i3(5, 5), 0.0);
    const ActionCovariance i6 = emslam::rectify::informationOf(c, 6);
    EXPECT_NEAR(i6(1, 1), 25.0, 1e-9);
    // ½ δᵀ Ω δ: one σ along x and two along θz.
    const ActionDelta d{0.1, 0, 0, 0, 0, 0.08};
    EXPECT_NEAR(emslam::rectify::halfMahalanobis(d, i6), 0.5 * (1.0 + 4.0), 1e-9);
    // A zero variance is floored, not inverted to infinity.
    ActionCovariance z;
    z.setZero();
    const ActionCovariance iz = emslam::rectify::informationOf(z, 6, 1e-6);
    EXPECT_NEAR(iz(0, 0), 1e6, 1e-3);
}

TEST(ActionCovariance, aFailedStepMayBeOffByItsWholeMotion)
{
    const CPose3D v(0.3, 0, 0.4, mrpt::DEG2RAD(10), 0, 0);
    const ActionCovariance c = emslam::rectify::predictionCovariance(v, 0.1, mrpt::DEG2RAD(3.0));
    EXPECT_NEAR(std::sqrt(c(0, 0)), 0.5, 1e-12);
    EXPECT_NEAR(std::sqrt(c(3, 3)), mrpt::DEG2RAD(10.0), 1e-9);
    // Standing still: the floors.
    const ActionCovariance s = emslam::rectify::predictionCovariance(CPose3D(), 0.1, 0.05);
    EXPECT_NEAR(std::sqrt(s(2, 2)), 0.1, 1e-12);
    EXPECT_NEAR(std::sqrt(s(4, 4)), 0.05, 1e-12);
}
