// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Trajectory.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <functional>
#include <vector>

namespace emslam::rectify
{
/** Pose of an original frame in the world, by its frame index (e.g. the
 * ground truth, or the egomotion). */
using FramePoseLookup = std::function<mrpt::poses::CPose3D(std::size_t frame_index)>;

/** Pose of every element of `t` when each element's first frame is put at
 * `T_world_frame(frame_index)`; with a 3DOF energy the actions between them
 * are made planar, as the trajectory keeps them. \ingroup emslam_rectify_grp */
std::vector<mrpt::poses::CPose3D> elementPosesAt(
    const Trajectory& t, const FramePoseLookup& T_world_frame);

/** The entropy (the paper's energy, without any odometry prior) of the map of
 * `t`'s simplified observations placed at `element_poses` (one per element).
 * Evaluating it at the ground truth, at the egomotion and at the rectified
 * poses tells whether a rectification failed because the search stopped
 * short (the truth has less energy) or because the energy's minimum is not
 * at the truth. With `grid_phases` > 1, the mean over that many shifted
 * voxel grids, as Trajectory::setGridPhases() computes it. `t` does not
 * change. \ingroup emslam_rectify_grp */
double entropyAtElementPoses(
    const Trajectory& t,
    const std::vector<mrpt::poses::CPose3D>& element_poses,
    int grid_phases = 1);

/** The entropy of that map on the k-th of `phases` voxel grids, shifted by
 * k/phases of a cell along each axis (k = 0: `t`'s own grid). */
double entropyOnShiftedGrid(
    const Trajectory& t, const std::vector<mrpt::poses::CPose3D>& element_poses, int k, int phases);

/** The odometry prior's part of `t`'s energy (Trajectory::priorEnergyOf())
 * with its elements at `element_poses`: beside entropyAtElementPoses(), does
 * the prior let the rectifier reach those poses? 0 when the prior is off.
 * \ingroup emslam_rectify_grp */
double priorAtElementPoses(
    const Trajectory& t, const std::vector<mrpt::poses::CPose3D>& element_poses);

}  // namespace emslam::rectify
