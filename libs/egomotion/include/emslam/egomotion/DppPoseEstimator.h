// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include <array>
#include <vector>

namespace emslam::egomotion
{
/** Stage 4 of §2.1: the action (R, t) that maps current-frame points into
 * the previous frame, M_hat = R b + t, minimising E = sum_i Dpp(a_i, M_hat_i)
 * (Eq. 4, 7): the product of the two point-to-ray distances, which ignores
 * each point's depth noise along its own camera ray. Minimised by alternating
 * conjugate gradient on the translation and on the rotation, with an adaptive
 * step, until neither changes; optionally polished by Levenberg-Marquardt on
 * all six parameters at once (TParameters::joint_refinement).
 * \ingroup emslam_egomotion_grp */
class DppPoseEstimator
{
public:
    /** Options of the minimisation. */
    struct TParameters
    {
        /** Start from the closed-form Euclidean (Horn/Umeyama) fit instead of
         * identity. Not in the paper: an option, measured. */
        bool euclidean_init{true};
        int max_alternations{50};   //!< translation/rotation rounds
        int max_cg_iterations{50};  //!< per conjugate-gradient run
        double tolerance{1e-7};     //!< relative energy change that counts as "no change"
        /** After the alternating conjugate gradient, Levenberg-Marquardt on
         * the six parameters jointly, from where it stopped. Not in the
         * paper: the alternation stops short where a rotation and a
         * translation trade off; an option, measured (doc/apps/emslam-odometry.md). */
        bool joint_refinement{false};
    };

    /** The pose that minimises the Dpp energy, with its covariance. */
    struct Result
    {
        mrpt::poses::CPose3D T_prev_cur;  //!< pose of the current camera in the previous one
        double energy{0};                 //!< final sum of Dpp [m^2]
        double initial_energy{0};         //!< sum of Dpp at the initial pose [m^2]
        int alternations{0};              //!< translation/rotation rounds run
        int evaluations{0};               //!< energy/gradient evaluations
        /** Covariance of T_prev_cur from the curvature of E at its minimum,
         * each Dpp read as a squared residual r² (a product of two
         * distances): σ² (JᵀJ)⁻¹, J the rows ∇r, σ² = E / (n − 6) (Gauss-Newton;
         * the exact Hessian is indefinite near zero residuals). Order [x, y, z,
         * θx, θy, θz] for the perturbation (R exp(θ), t + δt), the one the
         * rectifier applies to its actions. Valid only if has_covariance. */
        mrpt::math::CMatrixDouble66 covariance;
        /** False when JᵀJ is not positive definite (degenerate geometry) or
         * there are fewer than 7 pairs. */
        bool has_covariance{false};
    };

    DppPoseEstimator() = default;
    /** An estimator with the options `p`. */
    explicit DppPoseEstimator(const TParameters& p) : m_params(p) {}
    /** The options it runs with. */
    const TParameters& parameters() const { return m_params; }

    /** Dpp of Eq. 7 for one pair: `a` in the previous frame, `b_hat` = R b + t,
     * `t` the current camera centre in the previous frame. */
    static double dpp(
        const mrpt::math::TPoint3D& a,
        const mrpt::math::TPoint3D& b_hat,
        const mrpt::math::TPoint3D& t);

    /** Energy E of Eq. 4 at pose `T_prev_cur` = (R, t) and, if asked, its
     * analytic gradient with respect to t (`grad_t`, [m]) and to a rotation
     * vector w applied on the left, R <- exp(w) R (`grad_w`, [m^2/rad]).
     * Pairs that are not finite are ignored. */
    static double energy(
        const std::vector<mrpt::math::TPoint3Df>& a,
        const std::vector<mrpt::math::TPoint3Df>& b,
        const mrpt::poses::CPose3D& T_prev_cur,
        std::array<double, 3>* grad_t = nullptr,
        std::array<double, 3>* grad_w = nullptr);

    /** The closed-form least-squares Euclidean fit (Horn/Umeyama, no scale):
     * the optional initialisation of estimate(), also a baseline for tests.
     * Needs >= 3 non-collinear pairs. */
    static mrpt::poses::CPose3D euclideanFit(
        const std::vector<mrpt::math::TPoint3Df>& a, const std::vector<mrpt::math::TPoint3Df>& b);

    /** The covariance of `T_prev_cur` at the minimum of E (see
     * Result::covariance); false if it is not defined. */
    static bool covarianceAt(
        const std::vector<mrpt::math::TPoint3Df>& a,
        const std::vector<mrpt::math::TPoint3Df>& b,
        const mrpt::poses::CPose3D& T_prev_cur,
        mrpt::math::CMatrixDouble66& covariance);

    /** Estimates T_prev_cur from matched points (a[i] <-> b[i]); needs >= 3 pairs. */
    Result estimate(
        const std::vector<mrpt::math::TPoint3Df>& a,
        const std::vector<mrpt::math::TPoint3Df>& b,
        const mrpt::poses::CPose3D& initial_guess = mrpt::poses::CPose3D()) const;

private:
    TParameters m_params;
};

}  // namespace emslam::egomotion
