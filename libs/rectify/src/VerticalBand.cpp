// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/VerticalBand.h>

namespace emslam::rectify
{
emslam::maps::WeightedPointCloud keepVerticalBand(
    const emslam::maps::WeightedPointCloud& cloud, double min_y, double max_y)
{
    emslam::maps::WeightedPointCloud out;
    out.points.reserve(cloud.size());
    out.weights.reserve(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
        const float y = cloud.points[i].y;
        if (y >= min_y && y <= max_y)
        {
            out.push_back(cloud.points[i], cloud.weights[i]);
        }
    }
    return out;
}

}  // namespace emslam::rectify
