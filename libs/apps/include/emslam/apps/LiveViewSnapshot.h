// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/img/CImage.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace emslam::apps
{
/** The state of a run that the live viewer shows; a newer snapshot replaces an
 * older one not yet drawn. Map points are not part of it: they accumulate
 * (LiveViewer::addMapPoints()). Everything is in the map frame (the first
 * camera's: x right, y down, z forward).
 * \ingroup emslam_apps_grp \sa LiveViewer */
struct LiveViewSnapshot
{
    /** Egomotion positions of every frame so far [m] (red). */
    std::vector<mrpt::math::TPoint3Df> egomotion;
    /** Positions of the accepted frames as rectified so far [m] (green). */
    std::vector<mrpt::math::TPoint3Df> slam;
    /** The loops closed so far: both ends at their positions in `slam` [m]
     * (orange segments). */
    std::vector<std::pair<mrpt::math::TPoint3Df, mrpt::math::TPoint3Df>> loops;
    /** The current camera pose T_world_cam, drawn as a frustum. */
    std::optional<mrpt::poses::CPose3D> camera;
    /** The current left (reference) image; empty: none. Give the viewer its
     * own pixels (a deep copy) if the producer reuses the buffer. */
    mrpt::img::CImage image;
    /** One status line (frame count, energy, ...). */
    std::string status;
};

}  // namespace emslam::apps
