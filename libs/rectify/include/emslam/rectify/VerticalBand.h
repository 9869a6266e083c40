// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/maps/WeightedPointCloud.h>

namespace emslam::rectify
{
/** The points of `cloud` (camera frame, y down) with min_y <= y <= max_y.
 * \ingroup emslam_rectify_grp \sa TRectifierOptions::vertical_band */
emslam::maps::WeightedPointCloud keepVerticalBand(
    const emslam::maps::WeightedPointCloud& cloud, double min_y, double max_y);

}  // namespace emslam::rectify
