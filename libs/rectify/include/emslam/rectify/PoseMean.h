// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <vector>

namespace emslam::rectify
{
/** Mean of poses that lie close together (e.g. one pose as found by several
 * independent rectifications): the arithmetic mean of the translations and
 * the normalised sum of the unit quaternions, each turned to the first's
 * hemisphere. For rotations a few degrees apart this is the rotation that
 * minimises the summed squared chordal distance; yaw-only inputs (3DOF) give
 * a yaw-only mean. Throws std::invalid_argument on an empty list.
 * \ingroup emslam_rectify_grp */
mrpt::poses::CPose3D meanPose(const std::vector<mrpt::poses::CPose3D>& poses);

}  // namespace emslam::rectify
