// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <cstddef>

namespace emslam::rectify
{
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
 * \ingroup emslam_rectify_grp */
struct OdometryPrior
{
    double weight{0.0};         //!< [nats] per unit squared Mahalanobis distance ×2
    double sigma_xyz{0.02};     //!< [m] translation deviation of one accepted step
    double sigma_rot_deg{0.5};  //!< [deg] rotation deviation of one accepted step

    bool enabled() const { return weight > 0.0; }
    /** The prior cost of `action` against the egomotion's `reference`, spanning
     * `steps` (≥ 1) accepted frames. */
    double cost(
        const mrpt::poses::CPose3D& action,
        const mrpt::poses::CPose3D& reference,
        std::size_t steps) const;
};

}  // namespace emslam::rectify
