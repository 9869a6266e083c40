// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Trajectory.h>
#include <emslam/slam/FusedPointCloud.h>
#include <emslam/slam/KeyframeScan.h>

#include <vector>

namespace emslam::slam
{
/** The keyframe scans (each in its camera frame) placed at their poses
 * (T_world_frame by frame index) and fused (FusedPointCloud::fuse() done):
 * each scan is a view from its camera's position. Scans whose frame has no
 * pose are left out. \ingroup emslam_slam_grp */
FusedPointCloud fuseScans(
    const std::vector<KeyframeScan>& scans,
    const std::vector<emslam::rectify::TimedPose>& poses,
    const FusedPointCloud::TOptions& options);

/** The same scans with every point replaced by the fused point it joined
 * (back in the scan's camera frame, with the fused sigma), the points of
 * dropped voxels left out: rays from the keyframes that end on the fused,
 * gated surfaces (map.bt). `fused` is fuseScans() of the same scans and
 * poses. \ingroup emslam_slam_grp */
std::vector<KeyframeScan> scansOnFusedSurfaces(
    const std::vector<KeyframeScan>& scans,
    const std::vector<emslam::rectify::TimedPose>& poses,
    const FusedPointCloud& fused);

}  // namespace emslam::slam
