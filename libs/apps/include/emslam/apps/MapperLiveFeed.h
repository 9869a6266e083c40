// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/LiveViewer.h>
#include <emslam/slam/EntropySlam.h>

#include <string>

namespace emslam::apps
{
/** Feeds a LiveViewer from a running Mapper (`emslam-mapper --viewer`):
 * after every processed frame, the points of an accepted frame are added
 * at its egomotion pose (the live map is not rectified; map.3Dscene holds
 * the rectified one; `[EntropySlam] export_max_height` cuts it as it cuts
 * map.3Dscene), and, only when the viewer is ready to draw, a snapshot
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
};

}  // namespace emslam::apps
