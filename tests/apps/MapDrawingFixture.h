// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/MapDrawingContent.h>

namespace emslam::test
{
/** A known map to draw: a 10 m x 6 m room seen by a camera 1 m above the
 * floor (floor at y = +1, ceiling at y = −2 in the first camera's frame, so
 * heights −1 .. 2 m), with walls; an egomotion loop around the room's
 * middle, a SLAM loop 0.5 m inside it, a ground truth 0.5 m outside it, and
 * an entropy map of the same points. */
struct MapDrawingFixture
{
    MapDrawingFixture();

    emslam::slam::IntensityCloud cloud;
    emslam::io::TumTrajectory egomotion, slam, ground_truth;
    emslam::CEntropyVoxelMap entropy_map;
    /** One loop closure, from a SLAM corner into the room, away from the
     * room's middle. */
    std::vector<std::pair<mrpt::math::TPoint3D, mrpt::math::TPoint3D>> loops{
        {{-1.0, 0.0, 2.5}, {1.0, 0.0, 4.0}}};

    /** Everything above, with no height cut. */
    emslam::apps::MapDrawingContent content() const;
};
}  // namespace emslam::test
