// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/LiveViewer.h>
#include <emslam/slam/EntropySlam.h>
#include <emslam/slam/StreamingVoxelFusion.h>

#include <optional>
#include <string>

namespace emslam::apps
{
/** Feeds a LiveViewer from a running Mapper (`emslam-mapper --viewer`):
 * after every processed frame, the points of an accepted frame are fused at
 * its egomotion pose (StreamingVoxelFusion: weighted by their depth
 * uncertainty, one point per `[EntropySlam] fused_voxel_size` cell, shown once
 * its fused σ is within `max_point_sigma`; the live map is not rectified,
 * map.3Dscene holds the rectified one; `[EntropySlam] export_max_height` cuts it
 * as it cuts map.3Dscene), and, only when the viewer is ready to draw, a snapshot
 * (trajectories, camera, left image, status) is built and pushed, so a slow
 * window costs the pipeline nothing but a flag check.
 * \ingroup emslam_apps_grp \sa LiveViewer */
class MapperLiveFeed
{
public:
    /** Opens the viewer (or warns and stays off without a display). */
    explicit MapperLiveFeed(const std::string& title);

    /** Call after each Mapper::process() that returned true. */
    void update(const slam::EntropySlam& m);

    /** The window it draws into. */
    const LiveViewer& viewer() const { return m_viewer; }

private:
    LiveViewer m_viewer;
    std::optional<slam::StreamingVoxelFusion> m_fusion;  //!< from the first frame's parameters
};

}  // namespace emslam::apps
