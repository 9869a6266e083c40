// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <vector>

namespace emslam::test
{
/** One-metre steps round a 10 m square (camera frame: z forward, turning
 * about y at every 10th step): `steps` + 1 poses, pose 40 is pose 0 again. */
std::vector<mrpt::poses::CPose3D> squareLoop(int steps);

/** Distance between the positions of two poses [m]. */
double distance(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b);

/** RMS position difference of two equally long pose lists [m], no alignment. */
double positionRmse(
    const std::vector<mrpt::poses::CPose3D>& a, const std::vector<mrpt::poses::CPose3D>& b);

}  // namespace emslam::test
