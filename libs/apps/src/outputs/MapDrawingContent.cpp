// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/MapDrawingContent.h>
#include <emslam/apps/MapStyle.h>

#include <cmath>

namespace emslam::apps
{
slam::IntensityCloud cutAboveHeight(const slam::IntensityCloud& cloud, double max_height)
{
    if (std::isinf(max_height) && max_height > 0)
    {
        return cloud;
    }
    slam::IntensityCloud out;
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
        if (heightAboveFirstCamera(cloud.points[i]) <= max_height)
        {
            out.points.push_back(cloud.points[i]);
            out.intensity.push_back(cloud.intensity[i]);
            if (cloud.hasSigma())
            {
                out.sigma.push_back(cloud.sigma[i]);
            }
        }
    }
    return out;
}

}  // namespace emslam::apps
