// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/DepthNoiseModel.h>

#include <cmath>

namespace emslam::slam
{
DepthNoiseModel::DepthNoiseModel(
    const mrpt::img::TStereoCamera& camera, double sigma_disparity_px, double rgbd_coefficient)
    : m_k(rgbd_coefficient)
{
    const double f = camera.leftCamera.fx();
    const double b =
        (std::hypot(camera.rightCameraPose.x, camera.rightCameraPose.y, camera.rightCameraPose.z));
    if (f > 0 && b > 0 && std::isfinite(f * b))
    {
        m_k = sigma_disparity_px / (f * b);
    }
}

}  // namespace emslam::slam
