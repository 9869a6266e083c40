// SPDX-License-Identifier: BSD-3-Clause
#include "PoseErrors.h"

#include <emslam/egomotion/DppPoseEstimator.h>
#include <emslam/util/CpuDispatch.h>

#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/Lie/SO.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using emslam::egomotion::DppPoseEstimator;
using emslam::test::rotationErrorDeg;
using emslam::test::translationError;
using mrpt::math::TPoint3D;
using mrpt::math::TPoint3Df;
using mrpt::poses::CPose3D;

namespace
{
TPoint3Df toF(const TPoint3D& p)
{
    return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

/** Left-multiplies the rotation of T by exp(w). */
CPose3D rotateLeft(const CPose3D& T, const mrpt::math::CVectorFixedDouble<3>& w)
{
    const auto R = mrpt::poses::Lie::SO<3>::exp(w);
    CPose3D out = T;
    out.setRotationMatrix(R * T.getRotationMatrix());
    return out;
}

/** Stereo-like matched points for a known motion T_prev_cur. A camera with
 * f = 500 px and a 0.12 m baseline sees points at 2-20 m (or between
 * `z_near` and `z_far`); each point gets the noise of its own stereo
 * reconstruction: `disp_sigma` px of disparity noise
 * (a depth error along its ray that grows with z^2) and 0.3 px of pixel noise
 * across it. */
void makeStereoPairs(
    const CPose3D& T_prev_cur,
    int n,
    double disp_sigma,
    unsigned seed,
    std::vector<TPoint3Df>& a,
    std::vector<TPoint3Df>& b,
    double z_near = 2.0,
    double z_far = 20.0)
{
    const double f = 500, B = 0.12;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::normal_distribution<double> N(0.0, 1.0);
    auto noisy = [&](const TPoint3D& p)
    {
        const double z = p.z;
        const double dz = z * z / (f * B) * disp_sigma * N(rng);
        const double s = (z + dz) / z;  // along the ray through the camera centre
        const double lat = z / f * 0.3;
        return toF({p.x * s + lat * N(rng), p.y * s + lat * N(rng), p.z * s});
    };
    a.clear();
    b.clear();
    while (static_cast<int>(a.size()) < n)
    {
        // Uniform in the image (640x480) and in inverse depth, as stereo gives.
        const double u = 640 * U(rng) - 320, v = 480 * U(rng) - 240;
        const double z = 1.0 / (1.0 / z_far + (1.0 / z_near - 1.0 / z_far) * U(rng));
        const TPoint3D pa(u * z / f, v * z / f, z);
        const TPoint3D pb = T_prev_cur.inverseComposePoint(pa);
        if (pb.z < 1.0)
        {
            continue;  // behind the current camera
        }
        a.push_back(noisy(pa));
        b.push_back(noisy(pb));
    }
}

}  // namespace

TEST(DppPoseEstimator, dppOfEq7)
{
    // a on the optical axis at 4 m; b_hat 1 m to its side, seen from t = 0:
    // both point-to-ray distances are 1 m * sin(angle) terms.
    const TPoint3D a(0, 0, 4), b_hat(1, 0, 4), t(0, 0, 0);
    const double d1 = 4.0 / std::sqrt(17.0);  // a to the ray through b_hat
    const double d2 = 1.0;                    // b_hat to the optical axis
    EXPECT_NEAR(DppPoseEstimator::dpp(a, b_hat, t), d1 * d2, 1e-12);
    // Noise along either ray costs nothing.
    EXPECT_NEAR(DppPoseEstimator::dpp(a, TPoint3D(0, 0, 9), t), 0.0, 1e-12);
    // Points at a camera centre define no ray: guarded, finite.
    EXPECT_EQ(DppPoseEstimator::dpp(TPoint3D(0, 0, 0), b_hat, t), 0.0);
    EXPECT_EQ(DppPoseEstimator::dpp(a, TPoint3D(1, 2, 3), TPoint3D(1, 2, 3)), 0.0);
}

TEST(DppPoseEstimator, analyticGradientMatchesCentralDifferences)
{
    const CPose3D T(0.2, -0.1, 0.7, 0.08, -0.05, 0.03);
    std::vector<TPoint3Df> a, b;
    makeStereoPairs(T, 60, 0.5, 11, a, b);
    // Evaluate away from the optimum so that the gradient is not ~0.
    const CPose3D T0(0.25, -0.05, 0.6, 0.1, -0.02, 0.0);
    std::array<double, 3> gt{}, gw{};
    DppPoseEstimator::energy(a, b, T0, &gt, &gw);
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k)
    {
        CPose3D tp = T0, tm = T0;
        tp.x_incr(k == 0 ? h : 0);
        tp.y_incr(k == 1 ? h : 0);
        tp.z_incr(k == 2 ? h : 0);
        tm.x_incr(k == 0 ? -h : 0);
        tm.y_incr(k == 1 ? -h : 0);
        tm.z_incr(k == 2 ? -h : 0);
        const double num_t =
            (DppPoseEstimator::energy(a, b, tp) - DppPoseEstimator::energy(a, b, tm)) / (2 * h);
        EXPECT_NEAR(gt[k], num_t, 1e-5 * std::max(1.0, std::abs(num_t))) << "d/dt" << k;

        mrpt::math::CVectorFixedDouble<3> w;
        w.setZero();
        w[k] = h;
        const double ep = DppPoseEstimator::energy(a, b, rotateLeft(T0, w));
        w[k] = -h;
        const double em = DppPoseEstimator::energy(a, b, rotateLeft(T0, w));
        const double num_w = (ep - em) / (2 * h);
        EXPECT_NEAR(gw[k], num_w, 1e-5 * std::max(1.0, std::abs(num_w))) << "d/dw" << k;
    }
}

TEST(DppPoseEstimator, recoversKnownMotionFromIdentity)
{
    const CPose3D T(0.3, -0.1, 1.0, 0.0873, 0.0349, -0.0524);  // 5, 2, -3 deg
    std::vector<TPoint3Df> a, b;
    makeStereoPairs(T, 300, 0.2, 5, a, b);
    DppPoseEstimator::TParameters p;
    p.euclidean_init = false;  // the conjugate gradient alone, from identity
    p.max_alternations = 200;
    const auto r = DppPoseEstimator(p).estimate(a, b);
    std::printf(
        "from identity: t err %.4f m, R err %.4f deg, E %.3g -> %.3g, %d alternations, %d evals\n",
        translationError(r.T_prev_cur, T), rotationErrorDeg(r.T_prev_cur, T), r.initial_energy,
        r.energy, r.alternations, r.evaluations);
    EXPECT_LT(translationError(r.T_prev_cur, T), 0.03);
    EXPECT_LT(rotationErrorDeg(r.T_prev_cur, T), 0.2);
    EXPECT_LT(r.energy, r.initial_energy);
}

TEST(DppPoseEstimator, recoversKnownMotionWithEuclideanInit)
{
    const CPose3D T(-0.2, 0.05, 0.8, -0.1, 0.02, 0.04);
    std::vector<TPoint3Df> a, b;
    makeStereoPairs(T, 300, 0.2, 6, a, b);
    const auto r = DppPoseEstimator().estimate(a, b);
    EXPECT_LT(translationError(r.T_prev_cur, T), 0.03);
    EXPECT_LT(rotationErrorDeg(r.T_prev_cur, T), 0.2);
}

// The point of Dpp (§2.1.4): with depth noise along the rays it beats the
// Euclidean least-squares fit on the same pairs.
TEST(DppPoseEstimator, dppBeatsEuclideanOnStereoNoise)
{
    const CPose3D T(0.1, -0.05, 1.2, 0.05, -0.03, 0.02);
    double sum_t_dpp = 0, sum_t_euc = 0, sum_r_dpp = 0, sum_r_euc = 0;
    const int seeds = 10;
    for (int s = 0; s < seeds; ++s)
    {
        std::vector<TPoint3Df> a, b;
        makeStereoPairs(T, 200, 0.5, 1000 + s, a, b);
        const CPose3D euc = DppPoseEstimator::euclideanFit(a, b);
        const auto dpp = DppPoseEstimator().estimate(a, b);
        sum_t_euc += translationError(euc, T);
        sum_t_dpp += translationError(dpp.T_prev_cur, T);
        sum_r_euc += rotationErrorDeg(euc, T);
        sum_r_dpp += rotationErrorDeg(dpp.T_prev_cur, T);
    }
    std::printf(
        "mean over %d seeds: Euclidean %.4f m / %.4f deg, Dpp %.4f m / %.4f deg\n", seeds,
        sum_t_euc / seeds, sum_r_euc / seeds, sum_t_dpp / seeds, sum_r_dpp / seeds);
    EXPECT_LT(sum_t_dpp, 0.7 * sum_t_euc);
    EXPECT_LT(sum_r_dpp, 0.7 * sum_r_euc);
}

// The energy loops run on AVX2 where the CPU has it and on the x86-64
// baseline elsewhere (util/CpuDispatch.h): one build must give one answer.
// AVX2 without fused multiply-add rounds as the baseline, so the whole
// minimisation (hundreds of evaluations, each a sum of 300 terms) must end on
// the same bits, not merely close.
TEST(DppPoseEstimator, avx2AndBaselineLoopsGiveTheSameBits)
{
    emslam::util::setBaselineOnly(false);
    if (!emslam::util::avx2Enabled())
    {
        GTEST_SKIP() << "this CPU (or EMSLAM_SIMD) runs the baseline loops only";
    }
    const CPose3D T(0.2, -0.1, 1.0, 0.08, -0.02, 0.05);
    std::vector<TPoint3Df> a, b;
    makeStereoPairs(T, 301, 0.5, 77, a, b);  // 301: a remainder after the 4-wide loop
    DppPoseEstimator::TParameters p;
    p.joint_refinement = true;
    const DppPoseEstimator dpp(p);
    const auto wide = dpp.estimate(a, b);
    std::array<double, 3> gt_wide{}, gw_wide{};
    const double e_wide = DppPoseEstimator::energy(a, b, T, &gt_wide, &gw_wide);
    emslam::util::setBaselineOnly(true);
    const auto base = dpp.estimate(a, b);
    std::array<double, 3> gt_base{}, gw_base{};
    const double e_base = DppPoseEstimator::energy(a, b, T, &gt_base, &gw_base);
    emslam::util::setBaselineOnly(false);

    EXPECT_EQ(e_wide, e_base);
    EXPECT_EQ(gt_wide, gt_base);
    EXPECT_EQ(gw_wide, gw_base);
    EXPECT_EQ(wide.evaluations, base.evaluations);
    EXPECT_EQ(wide.energy, base.energy);
    for (int k = 0; k < 12; ++k)
    {
        EXPECT_EQ(
            wide.T_prev_cur.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>()(k / 4, k % 4),
            base.T_prev_cur.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>()(k / 4, k % 4));
    }
    // And the answer is the motion, so the comparison is not of two failures.
    EXPECT_LT(translationError(wide.T_prev_cur, T), 0.05);
}

// A turn in front of a wall: the scene is a slab 3-3.3 m ahead, so a small
// rotation about the vertical and a sideways step move its points almost
// alike. The paper's alternating blocks stop in that valley short of the
// minimum; the joint Levenberg-Marquardt polish goes down it.
TEST(DppPoseEstimator, jointRefinementFinishesWhereTheAlternationStopsShort)
{
    const CPose3D T(0, 0, 0, 0, 6.0 * M_PI / 180, 0);  // 6 deg about the vertical (y)
    double err_alt = 0, err_joint = 0;
    const int draws = 10;
    for (int s = 0; s < draws; ++s)
    {
        std::vector<TPoint3Df> a, b;
        makeStereoPairs(T, 150, 0.3, 2000 + s, a, b, 3.0, 3.3);
        DppPoseEstimator::TParameters p;
        const auto alt = DppPoseEstimator(p).estimate(a, b);
        p.joint_refinement = true;
        const auto joint = DppPoseEstimator(p).estimate(a, b);
        EXPECT_LE(joint.energy, alt.energy);
        err_alt += rotationErrorDeg(alt.T_prev_cur, T);
        err_joint += rotationErrorDeg(joint.T_prev_cur, T);
    }
    std::printf(
        "mean rotation error: alternating %.4f deg, joint %.4f deg\n", err_alt / draws,
        err_joint / draws);
    EXPECT_LT(err_joint, 0.5 * err_alt);
}

TEST(DppPoseEstimator, needsThreePairs)
{
    const std::vector<TPoint3Df> a{{0, 0, 1}, {1, 0, 1}}, b = a;
    EXPECT_ANY_THROW(DppPoseEstimator().estimate(a, b));
}

TEST(DppPoseEstimator, covariancePredictsTheSpreadOfTheEstimates)
{
    // The covariance from the curvature of E must describe how the estimate
    // scatters over noise draws: compare, per component, the deviation of the
    // errors over 60 draws with the mean predicted one.
    const CPose3D T(0.1, -0.05, 1.2, 0.05, -0.03, 0.02);
    const int draws = 60;
    emslam::test::CovarianceCheck check;
    int with_covariance = 0;
    for (int s = 0; s < draws; ++s)
    {
        std::vector<TPoint3Df> a, b;
        makeStereoPairs(T, 150, 0.5, 2000 + s, a, b);
        const auto r = DppPoseEstimator().estimate(a, b);
        if (!r.has_covariance)
        {
            continue;
        }
        ++with_covariance;
        check.add(r.T_prev_cur, T, r.covariance);
    }
    ASSERT_EQ(with_covariance, draws);
    // Never over-confident (60 draws estimate a deviation within ~±10 %),
    // and cautious by at most ~4×: Dpp ignores the noise along each ray,
    // so the directions that noise dominates come out wider.
    check.expectWithin(0.25, 1.25);
}

TEST(DppPoseEstimator, noCovarianceForDegenerateInput)
{
    // Six pairs: fewer than 7, σ² = E / (n − 6) is undefined.
    const CPose3D T(0.1, 0, 1.0, 0, 0, 0);
    std::vector<TPoint3Df> a, b;
    makeStereoPairs(T, 6, 0.5, 7, a, b);
    mrpt::math::CMatrixDouble66 c;
    EXPECT_FALSE(DppPoseEstimator::covarianceAt(a, b, T, c));
    EXPECT_FALSE(DppPoseEstimator().estimate(a, b).has_covariance);
}
