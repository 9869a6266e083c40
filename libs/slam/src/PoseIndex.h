// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Trajectory.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <unordered_map>
#include <vector>

namespace emslam::slam
{
/** World pose of each frame in a list of timed poses, by frame index. */
using PoseIndex = std::unordered_map<std::size_t, const mrpt::poses::CPose3D*>;

/** Indexes `poses` (which must outlive the index) by frame index. */
inline PoseIndex indexPoses(const std::vector<emslam::rectify::TimedPose>& poses)
{
    PoseIndex index;
    index.reserve(poses.size());
    for (const auto& p : poses)
    {
        index[p.frame_index] = &p.T_world_frame;
    }
    return index;
}
}  // namespace emslam::slam
