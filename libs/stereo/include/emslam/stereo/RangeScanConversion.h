// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/stereo/StereoFrame.h>

#include <mrpt/obs/CObservation3DRangeScan.h>

namespace emslam::stereo
{
/** Converts a StereoFrame to a stock `CObservation3DRangeScan`: intensity
 * image, depth image (range_is_depth, `rangeUnits` metres per unit), and the 3D
 * points with their pixel indices. MRPT stores points in the sensor frame
 * +X forward, +Y left, +Z up; this function converts from the optical frame.
 * `cameraParams` and `cameraParamsIntensity` are the left camera.
 * \ingroup emslam_stereo_grp */
mrpt::obs::CObservation3DRangeScan::Ptr toRangeScan(
    const StereoFrame& frame, float range_units = 0.001f);

/** Builds a StereoFrame from a `CObservation3DRangeScan` (RGB-D camera or
 * toRangeScan() output). Uses the stored 3D points with pixel indices if
 * present, otherwise unprojects the range image with `cameraParams`. Throws if
 * the observation has neither an intensity image nor a range image.
 * \ingroup emslam_stereo_grp */
StereoFrame fromRangeScan(const mrpt::obs::CObservation3DRangeScan& obs);

}  // namespace emslam::stereo
