// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/sim/ExactDepthFrame.h>

#include <stdexcept>

namespace emslam::sim
{
emslam::stereo::StereoFrame exactDepthFrame(
    const StereoSimulator::Frame& f, double min_range, double max_range)
{
    if (!f.obs || f.depth.empty() || f.depth.type() != CV_32FC1)
    {
        throw std::invalid_argument("exactDepthFrame: the frame was rendered without its depth");
    }
    emslam::stereo::StereoFrame s;
    s.timestamp = f.obs->timestamp;
    s.sensor_label = f.obs->sensorLabel;
    s.intensity = f.obs->imageLeft.asCvMatRef().clone();
    s.camera = f.obs->getStereoCameraParams();
    s.valid = cv::Mat::zeros(f.depth.size(), CV_8UC1);
    const auto& cam = s.camera.leftCamera;
    const double fx = cam.fx(), fy = cam.fy(), cx = cam.cx(), cy = cam.cy();
    for (int v = 0; v < f.depth.rows; ++v)
    {
        const float* d = f.depth.ptr<float>(v);
        for (int u = 0; u < f.depth.cols; ++u)
        {
            const double z = d[u];
            if (!(z >= min_range && z <= max_range) || z <= 0)
            {
                continue;
            }
            s.points.emplace_back(
                static_cast<float>((u - cx) * z / fx), static_cast<float>((v - cy) * z / fy),
                static_cast<float>(z));
            s.pixels.push_back({static_cast<std::uint16_t>(u), static_cast<std::uint16_t>(v)});
            s.valid.at<std::uint8_t>(v, u) = 255;
        }
    }
    return s;
}

}  // namespace emslam::sim
