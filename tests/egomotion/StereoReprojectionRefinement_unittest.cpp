// SPDX-License-Identifier: BSD-3-Clause
#include "PoseErrors.h"

#include <emslam/egomotion/DppPoseEstimator.h>
#include <emslam/egomotion/StereoReprojectionRefinement.h>

#include <mrpt/poses/CPose3D.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

using emslam::egomotion::DppPoseEstimator;
using emslam::egomotion::StereoReprojectionRefinement;
using emslam::test::rotationErrorDeg;
using emslam::test::translationError;
using mrpt::math::TPoint3D;
using mrpt::math::TPoint3Df;
using mrpt::poses::CPose3D;

namespace
{
constexpr double F = 700;   // [px]
constexpr double B = 0.54;  // [m], a car's stereo head

/** Matched stereo points for a known motion T_prev_cur, with the noise of
 * features matched across frames: each point's pixel (u, v) is off by
 * `pixel_sigma` px in each frame, its disparity by `disp_sigma` px. */
void makePairs(
    const CPose3D& T_prev_cur,
    int n,
    double pixel_sigma,
    double disp_sigma,
    unsigned seed,
    std::vector<TPoint3Df>& a,
    std::vector<TPoint3Df>& b)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::normal_distribution<double> N(0.0, 1.0);
    auto observe = [&](const TPoint3D& p)
    {
        const double u = F * p.x / p.z + pixel_sigma * N(rng);
        const double v = F * p.y / p.z + pixel_sigma * N(rng);
        const double d = F * B / p.z + disp_sigma * N(rng);
        const double z = F * B / d;
        return TPoint3Df(
            static_cast<float>(u * z / F), static_cast<float>(v * z / F), static_cast<float>(z));
    };
    a.clear();
    b.clear();
    while (static_cast<int>(a.size()) < n)
    {
        // Uniform in a 1240x370 image and in inverse depth, 4-20 m.
        const double u = 1240 * U(rng) - 620, v = 370 * U(rng) - 185;
        const double z = 1.0 / (1.0 / 20.0 + (1.0 / 4.0 - 1.0 / 20.0) * U(rng));
        const TPoint3D pa(u * z / F, v * z / F, z);
        const TPoint3D pb = T_prev_cur.inverseComposePoint(pa);
        if (pb.z < 2.0)
        {
            continue;
        }
        a.push_back(observe(pa));
        b.push_back(observe(pb));
    }
}

const CPose3D MOTION(0.05, -0.02, 2.4, 0.02, -0.01, 0.005);  // a car's step of 2.4 m
}  // namespace

TEST(StereoReprojectionRefinement, recoversTheExactMotionWithoutNoise)
{
    std::vector<TPoint3Df> a, b;
    makePairs(MOTION, 80, 0, 0, 1, a, b);
    const CPose3D start = MOTION + CPose3D(0.05, 0.03, -0.08, 0.01, -0.01, 0.02);
    const auto r = StereoReprojectionRefinement::refine(a, b, start, B, F);
    EXPECT_EQ(r.pairs, 80u);
    EXPECT_GT(r.rms_initial_px, 1.0);
    EXPECT_LT(r.rms_final_px, 1e-3);
    // Float coordinates limit the exactness.
    EXPECT_LT(translationError(r.T_prev_cur, MOTION), 1e-4);
    EXPECT_LT(rotationErrorDeg(r.T_prev_cur, MOTION), 1e-3);
    EXPECT_TRUE(r.has_covariance);
}

// Features matched across frames sit a pixel or two apart while the
// disparity at each is good to a fraction of a pixel (real images: KITTI 06,
// doc/apps/emslam-odometry.md). Dpp trusts the bearings and discounts the
// depths; the reprojection error weighs each by its own noise.
TEST(StereoReprojectionRefinement, beatsDppWhenBearingsAreNoisierThanDisparities)
{
    double t_dpp = 0, r_dpp = 0, t_ref = 0, r_ref = 0;
    const int draws = 10;
    for (int s = 0; s < draws; ++s)
    {
        std::vector<TPoint3Df> a, b;
        makePairs(MOTION, 120, 1.5, 0.15, 100 + s, a, b);
        const auto dpp = DppPoseEstimator().estimate(a, b);
        const auto ref = StereoReprojectionRefinement::refine(a, b, dpp.T_prev_cur, B, F);
        t_dpp += translationError(dpp.T_prev_cur, MOTION);
        r_dpp += rotationErrorDeg(dpp.T_prev_cur, MOTION);
        t_ref += translationError(ref.T_prev_cur, MOTION);
        r_ref += rotationErrorDeg(ref.T_prev_cur, MOTION);
    }
    std::printf(
        "mean over %d draws: Dpp %.4f m / %.4f deg, reprojection %.4f m / %.4f deg\n", draws,
        t_dpp / draws, r_dpp / draws, t_ref / draws, r_ref / draws);
    EXPECT_LT(t_ref, 0.6 * t_dpp);
    EXPECT_LT(r_ref, 0.8 * r_dpp);
}

TEST(StereoReprojectionRefinement, wrongMatchesDoNotPullTheFit)
{
    std::vector<TPoint3Df> a, b;
    makePairs(MOTION, 120, 1.0, 0.1, 7, a, b);
    const auto clean = StereoReprojectionRefinement::refine(a, b, MOTION, B, F);
    // One match in ten is another point: 25-45 px off in the image.
    for (std::size_t i = 0; i < b.size(); i += 10)
    {
        const float shift = 0.05f * b[i].z * (i % 20 == 0 ? 1.0f : -1.0f);
        b[i].x += shift;
        b[i].y -= 0.5f * shift;
    }
    const auto dirty = StereoReprojectionRefinement::refine(a, b, MOTION, B, F);
    std::printf(
        "clean %.4f m / %.4f deg, with 10 %% wrong matches %.4f m / %.4f deg\n",
        translationError(clean.T_prev_cur, MOTION), rotationErrorDeg(clean.T_prev_cur, MOTION),
        translationError(dirty.T_prev_cur, MOTION), rotationErrorDeg(dirty.T_prev_cur, MOTION));
    EXPECT_LT(translationError(dirty.T_prev_cur, MOTION), 0.03);
    EXPECT_LT(rotationErrorDeg(dirty.T_prev_cur, MOTION), 0.05);
}

TEST(StereoReprojectionRefinement, covariancePredictsTheSpreadOfTheEstimates)
{
    const int draws = 60;
    emslam::test::CovarianceCheck check;
    for (int s = 0; s < draws; ++s)
    {
        std::vector<TPoint3Df> a, b;
        makePairs(MOTION, 120, 1.5, 0.15, 500 + s, a, b);
        const auto r = StereoReprojectionRefinement::refine(
            a, b, DppPoseEstimator().estimate(a, b).T_prev_cur, B, F);
        ASSERT_TRUE(r.has_covariance);
        check.add(r.T_prev_cur, MOTION, r.covariance);
    }
    // Measured within 12 % in every component; 60 draws estimate a
    // deviation within ~±10 %.
    check.expectWithin(0.75, 1.3);
}

TEST(StereoReprojectionRefinement, leavesThePoseAloneWithoutUsableInput)
{
    std::vector<TPoint3Df> a, b;
    makePairs(MOTION, 40, 1.0, 0.1, 3, a, b);
    const CPose3D start = MOTION + CPose3D(0.1, 0, 0, 0, 0, 0);
    // No baseline (a depth camera), or not a number.
    for (const double baseline : {0.0, -0.1, std::numeric_limits<double>::quiet_NaN()})
    {
        const auto r = StereoReprojectionRefinement::refine(a, b, start, baseline, F);
        EXPECT_EQ(r.T_prev_cur, start);
        EXPECT_FALSE(r.has_covariance);
    }
    // Three pairs, and pairs that are not finite or not in front of a camera.
    const std::vector<TPoint3Df> a3(a.begin(), a.begin() + 3), b3(b.begin(), b.begin() + 3);
    EXPECT_EQ(StereoReprojectionRefinement::refine(a3, b3, start, B, F).T_prev_cur, start);
    auto a_bad = a;
    a_bad[0].x = std::numeric_limits<float>::quiet_NaN();
    a_bad[1].z = -5;
    a_bad[2].z = 0;
    const auto r = StereoReprojectionRefinement::refine(a_bad, b, start, B, F);
    EXPECT_EQ(r.pairs, a.size() - 3);
    EXPECT_TRUE(r.has_covariance);
    EXPECT_LT(translationError(r.T_prev_cur, MOTION), 0.05);
}
