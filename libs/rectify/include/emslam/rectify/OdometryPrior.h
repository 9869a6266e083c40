// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/ActionCovariance.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace emslam::rectify
{
/** Where the prior's uncertainty comes from. */
enum class PriorCovariance : std::uint8_t
{
    /** σ_xyz and σ_rot per accepted step, the same for every step. */
    Fixed = 0,
    /** The egomotion's own covariance of each step (the curvature of its Dpp
     * minimum, DppPoseEstimator::Result::covariance), composed over the steps
     * an action spans; steps without one get σ_xyz / σ_rot. */
    Egomotion
};

/** An optional term added to the entropy, beside the paper: a Gaussian prior
 * that keeps each action near the egomotion's estimate of it,
 *
 *   E = H + Σ_{i≥1} cost(a_i, â_i, n_i),
 *   cost = weight/2 · (‖t(â⁻¹ ⊕ a)‖² / (n σ_xyz²) + θ(â⁻¹ ⊕ a)² / (n σ_rot²)),
 *
 * with â_i the egomotion action, n_i the accepted frames it spans (a random
 * walk: the variance grows with the steps fused by compression) and θ the
 * rotation angle of the difference. Why: the entropy is flat along a
 * corridor and in other degenerate directions, where hard-binning noise lets
 * the greedy search wander; the egomotion is locally accurate there, and a
 * loop's correction spread over many actions costs little (Σ (δ/N)² = δ²/N).
 * a_0 (the global alignment) has no prior. weight = 0 (the default) is the
 * paper's energy.
 *
 * With `covariance = Egomotion` the cost is the Mahalanobis form
 * weight · ½ δᵀ Σ⁻¹ δ, δ = actionDifference(a, â) and Σ the egomotion's
 * covariance of â (composed like the actions): directions the images pinned
 * down cost much, those they did not (a failed step, a textureless wall)
 * cost little.
 * \ingroup emslam_rectify_grp */
struct OdometryPrior
{
    double weight{0.0};         //!< [nats] per unit squared Mahalanobis distance ×2
    double sigma_xyz{0.02};     //!< [m] translation deviation of one accepted step
    double sigma_rot_deg{0.5};  //!< [deg] rotation deviation of one accepted step
    PriorCovariance covariance{PriorCovariance::Fixed};  //!< where Σ comes from: the sigmas above,
                                                         //!< or the egomotion's covariance

    /** The prior counts: weight > 0. */
    bool enabled() const { return weight > 0.0; }
    /** The prior cost of `action` against the egomotion's `reference`, spanning
     * `steps` (≥ 1) accepted frames. */
    double cost(
        const mrpt::poses::CPose3D& action,
        const mrpt::poses::CPose3D& reference,
        std::size_t steps) const;
    /** The Mahalanobis cost of `action` against `reference` whose information
     * matrix (inverse covariance) is `information`. */
    double cost(
        const mrpt::poses::CPose3D& action,
        const mrpt::poses::CPose3D& reference,
        const ActionCovariance& information) const;
    /** The covariance of one accepted step with the fixed deviations. */
    ActionCovariance stepCovariance() const;
};

/** INI names: `fixed`, `egomotion`. */
std::string toString(PriorCovariance c);

}  // namespace emslam::rectify
