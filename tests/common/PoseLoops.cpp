// SPDX-License-Identifier: BSD-3-Clause
#include "PoseLoops.h"

#include <mrpt/core/bits_math.h>

#include <cmath>

namespace emslam::test
{
std::vector<mrpt::poses::CPose3D> squareLoop(int steps)
{
    std::vector<mrpt::poses::CPose3D> truth{mrpt::poses::CPose3D()};
    for (int k = 1; k <= steps; ++k)
    {
        const double turn = (k % 10 == 0) ? mrpt::DEG2RAD(90.0) : 0.0;
        // Camera axes: yaw about the camera's y is CPose3D's pitch.
        truth.push_back(truth.back() + mrpt::poses::CPose3D(0, 0, 1, 0, turn, 0));
    }
    return truth;
}

double distance(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
    return (a.translation() - b.translation()).norm();
}

double positionRmse(
    const std::vector<mrpt::poses::CPose3D>& a, const std::vector<mrpt::poses::CPose3D>& b)
{
    double s = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        s += std::pow(distance(a[i], b[i]), 2);
    }
    return std::sqrt(s / static_cast<double>(a.size()));
}

}  // namespace emslam::test
