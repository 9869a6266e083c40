// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/sim/StereoSimulator.h>
#include <emslam/stereo/StereoFrame.h>

namespace emslam::sim
{
/** A rendered frame as a perfect depth camera would give it: the left image
 * and, for every pixel whose exact depth lies in [min_range, max_range] [m],
 * its 3D point in the left camera frame. The frame must have been rendered
 * with its depth (`renderFrame(i, true)`); throws std::invalid_argument
 * otherwise. Feeding toRangeScan() of it to the mapper instead of the
 * stereo pair separates what stereo noise does from what the method does.
 * \ingroup emslam_sim_grp */
emslam::stereo::StereoFrame exactDepthFrame(
    const StereoSimulator::Frame& f, double min_range, double max_range);

}  // namespace emslam::sim
