// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <array>
#include <vector>

namespace emslam::rectify
{
/** A perturbation of one action: [δx, δy, δz, δθx, δθy, δθz] in the action's
 * own (previous camera) frame, metres and radians. */
using ActionDelta = std::array<double, 6>;

/** The 3DOF part [δx, δz, δθ_y] of an action (camera frame: y is vertical):
 * δy, δθx and δθz are dropped. The rotation angle is the one about y that
 * best explains the action's rotation (exact for a planar action).
 * \ingroup emslam_rectify_grp */
mrpt::poses::CPose3D planarAction(const mrpt::poses::CPose3D& action);

/** `action` perturbed by `delta`: the translation gets [δx, δy, δz] added
 * and the rotation is followed by Exp([δθx, δθy, δθz]), i.e. turned about
 * the axes of the camera that ends the action. For small ε this is the
 * paper's uniform per-component perturbation U(a − ε, a + ε) (§2.2.3), and
 * unlike adding to Euler angles it has no singularity, so it also holds for
 * the large actions of a compressed trajectory. A 3DOF delta (only δx, δz,
 * δθ_y non-zero) keeps a planar action planar.
 * \ingroup emslam_rectify_grp */
mrpt::poses::CPose3D perturbAction(const mrpt::poses::CPose3D& action, const ActionDelta& delta);

/** Rotation angle of `T` [rad], in [0, π]. From sin and cos (atan2): acos of
 * (trace − 1) / 2 loses half the digits at the small angles of drift.
 * \ingroup emslam_rectify_grp */
double rotationAngle(const mrpt::poses::CPose3D& T);

/** The actions that put the elements at `element_poses`: a_0 = pose_0 (the
 * global alignment), a_i = pose_{i-1}⁻¹ ⊕ pose_i. \ingroup emslam_rectify_grp */
std::vector<mrpt::poses::CPose3D> actionsBetween(
    const std::vector<mrpt::poses::CPose3D>& element_poses);

}  // namespace emslam::rectify
