// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TumTrajectory.h>
#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/slam/IntensityCloud.h>

#include <mrpt/math/TPoint3D.h>

#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace emslam::apps
{
/** What a map drawing (map.3Dscene, map_top.png) shows; everything in the map
 * frame (the first camera's: x right, y down, z forward). Null pointers are
 * left out of the drawing. The pointees must outlive the call.
 * \ingroup emslam_apps_grp \sa buildMapScene(), renderTopView() */
struct MapDrawingContent
{
    const slam::IntensityCloud* cloud{nullptr};              //!< the map cloud
    const emslam::io::TumTrajectory* egomotion{nullptr};     //!< red
    const emslam::io::TumTrajectory* slam{nullptr};          //!< green
    const emslam::io::TumTrajectory* ground_truth{nullptr};  //!< blue, map frame
    const emslam::CEntropyVoxelMap* entropy_map{nullptr};    //!< its 3D cells
    /** Loop closures: the two ends of each (orange segments). */
    const std::vector<std::pair<mrpt::math::TPoint3D, mrpt::math::TPoint3D>>* loops{nullptr};
    /** Cloud points higher than this above the first camera (along −y) are
     * left out, e.g. to see the floor plan under a ceiling [m]; +inf: none. */
    double max_height{std::numeric_limits<double>::infinity()};
    /** At most this many (the heaviest) entropy cells are drawn. */
    std::size_t max_voxels{20000};
};

/** The points of `cloud` at most `max_height` above the first camera (up is
 * −y); +inf keeps every point. \ingroup emslam_apps_grp */
slam::IntensityCloud cutAboveHeight(const slam::IntensityCloud& cloud, double max_height);

}  // namespace emslam::apps
