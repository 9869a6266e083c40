// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/slam/IntensityCloud.h>

#include <cstddef>

namespace emslam::slam
{
/** What one keyframe's camera saw, kept for the final map: its points in its
 * camera frame, placed at the keyframe's final pose when the map is fused.
 * \ingroup emslam_slam_grp \sa KeyframeClouds, fuseScans() */
struct KeyframeScan
{
    std::size_t frame_index{0};  //!< the keyframe whose camera frame the cloud is in
    IntensityCloud cloud;        //!< the points, in that camera's frame
};

}  // namespace emslam::slam
