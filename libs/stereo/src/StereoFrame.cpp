// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/stereo/StereoFrame.h>

namespace emslam::stereo
{
double StereoFrame::density() const
{
    const double n = static_cast<double>(intensity.total());
    return n > 0 ? static_cast<double>(points.size()) / n : 0.0;
}
}  // namespace emslam::stereo
