// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::test
{
/** A stereo frame of the simulator with its exact pose. */
struct TruthFrame
{
    mrpt::obs::CObservationStereoImages::Ptr obs;
    /** Left camera in the first left camera's frame (the odometry's world). */
    mrpt::poses::CPose3D T_first_left;
};

/** The world INI of a small textured room with a central pillar, around
 * which a 3DOF robot drives a closed loop of about 21 m twice (320x240
 * stereo, `fps` frames per second at 1 m/s, holonomic: no turn on the
 * spot). */
std::string smallLoopWorldIni(double fps);

/** The first `count` frames (all if 0) of smallLoopWorldIni(`fps`),
 * rendered once per process and size. */
const std::vector<TruthFrame>& smallLoopFrames(double fps, std::size_t count = 0);

/** The rotation angle of `p` [deg]. */
double rotationDeg(const mrpt::poses::CPose3D& p);

}  // namespace emslam::test
