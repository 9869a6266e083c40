// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Action.h>

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>

namespace emslam::rectify
{
/** Covariance of an action, in the parametrisation of perturbAction():
 * [δx, δy, δz, δθx, δθy, δθz], the translation added, the rotation applied
 * on the right (R exp(δθ)). [m², m·rad, rad²] */
using ActionCovariance = mrpt::math::CMatrixDouble66;

/** The ActionDelta that perturbAction() needs to turn `reference` into
 * `action`: δt = t − t̂, δθ = Log(R̂ᵀ R). \ingroup emslam_rectify_grp */
ActionDelta actionDifference(
    const mrpt::poses::CPose3D& action, const mrpt::poses::CPose3D& reference);

/** Covariance of a1 ⊕ a2 from the (independent) covariances of a1 and a2,
 * to first order. \ingroup emslam_rectify_grp */
ActionCovariance composeCovariance(
    const mrpt::poses::CPose3D& a1,
    const ActionCovariance& c1,
    const mrpt::poses::CPose3D& a2,
    const ActionCovariance& c2);

/** Covariance of `fixed` ⊕ a2 when only a2 is uncertain (e.g. an action that
 * starts at a frame inside a compressed element). \ingroup emslam_rectify_grp */
ActionCovariance transportCovariance(const mrpt::poses::CPose3D& fixed, const ActionCovariance& c2);

/** Diagonal covariance: σ_xyz² on the translation, σ_rot² on the rotation. */
ActionCovariance diagonalCovariance(double sigma_xyz, double sigma_rot_rad);

/** The covariance given to a step the egomotion could not estimate: it is
 * predicted by constant velocity (the previous step), and each component may
 * be off by the whole predicted motion or by `min_sigma_xyz` / `min_sigma_rot_rad`,
 * whichever is larger, so the rectifier is free to move it.
 * \ingroup emslam_rectify_grp */
ActionCovariance predictionCovariance(
    const mrpt::poses::CPose3D& predicted, double min_sigma_xyz, double min_sigma_rot_rad);

/** The 3DOF marginal [δx, δz, δθy] of a covariance, embedded back into 6×6
 * with the other rows and columns zero. \ingroup emslam_rectify_grp */
ActionCovariance planarCovariance(const ActionCovariance& c);

/** The information matrix (inverse) of `c` restricted to the components
 * of `dof` (3: δx, δz, δθy; 6: all), zero elsewhere. Components whose
 * variance is below `min_variance` are raised to it first, so a perfectly
 * certain component cannot give an infinite weight. \ingroup emslam_rectify_grp */
ActionCovariance informationOf(const ActionCovariance& c, int dof, double min_variance = 1e-12);

/** ½ δᵀ Ω δ. \ingroup emslam_rectify_grp */
double halfMahalanobis(const ActionDelta& delta, const ActionCovariance& information);

}  // namespace emslam::rectify
