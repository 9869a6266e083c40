// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/stereo/RangeScanConversion.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/img/CImage.h>

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace emslam::stereo
{
mrpt::obs::CObservation3DRangeScan::Ptr toRangeScan(const StereoFrame& frame, float range_units)
{
    ASSERTMSG_(range_units > 0, "toRangeScan: range_units must be > 0");
    ASSERTMSG_(frame.points.size() == frame.pixels.size(), "toRangeScan: points/pixels mismatch");
    auto obs = mrpt::obs::CObservation3DRangeScan::Create();
    obs->timestamp = frame.timestamp;
    obs->sensorLabel = frame.sensor_label;
    obs->cameraParams = frame.camera.leftCamera;
    obs->cameraParamsIntensity = frame.camera.leftCamera;
    // relativePoseIntensityWRTDepth keeps its default: the two cameras coincide.

    obs->hasIntensityImage = !frame.intensity.empty();
    if (obs->hasIntensityImage)
    {
        obs->intensityImage = mrpt::img::CImage(frame.intensity, mrpt::img::DEEP_COPY);
    }

    const int rows = frame.intensity.rows, cols = frame.intensity.cols;
    obs->range_is_depth = true;
    obs->rangeUnits = range_units;
    obs->hasRangeImage = rows > 0 && cols > 0;
    if (obs->hasRangeImage)
    {
        obs->rangeImage_setSize(rows, cols);
        obs->rangeImage.setZero();
    }

    const std::size_t n = frame.points.size();
    obs->hasPoints3D = true;
    obs->resizePoints3DVectors(n);
    float max_z = 0.0f;
    constexpr float max_u16 = std::numeric_limits<uint16_t>::max();
    for (std::size_t i = 0; i < n; ++i)
    {
        const auto& p = frame.points[i];
        const auto& px = frame.pixels[i];
        // MRPT's 3D range scan frame: +X forward, +Y left, +Z up.
        obs->points3D_x[i] = p.z;
        obs->points3D_y[i] = -p.x;
        obs->points3D_z[i] = -p.y;
        obs->points3D_idxs_x[i] = px.u;
        obs->points3D_idxs_y[i] = px.v;
        max_z = std::max(max_z, p.z);
        if (obs->hasRangeImage && px.u < cols && px.v < rows)
        {
            obs->rangeImage(px.v, px.u) =
                static_cast<uint16_t>(std::min(max_u16, std::round(p.z / range_units)));
        }
    }
    obs->maxRange = max_z;
    return obs;
}

StereoFrame fromRangeScan(const mrpt::obs::CObservation3DRangeScan& obs)
{
    ASSERTMSG_(
        obs.hasIntensityImage && !obs.intensityImage.isEmpty(),
        "3D range scan '" + obs.sensorLabel + "' has no intensity image");
    ASSERTMSG_(
        obs.hasPoints3D || obs.hasRangeImage,
        "3D range scan '" + obs.sensorLabel + "' has neither 3D points nor a range image");

    StereoFrame f;
    f.timestamp = obs.timestamp;
    f.sensor_label = obs.sensorLabel;
    cv::Mat im = obs.intensityImage.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY);
    if (im.channels() == 3)
    {
        cv::cvtColor(im, im, cv::COLOR_BGR2GRAY);
    }
    ASSERTMSG_(im.depth() == CV_8U, "3D range scan: intensity image must be 8-bit");
    f.intensity = im;
    f.valid = cv::Mat::zeros(im.size(), CV_8UC1);
    f.camera.leftCamera = obs.cameraParamsIntensity;
    f.camera.rightCamera = obs.cameraParamsIntensity;
    f.camera.rightCameraPose = mrpt::math::TPose3DQuat();  // no baseline: not a stereo pair

    auto add = [&](float x, float y, float z, int u, int v)
    {
        if (u < 0 || v < 0 || u >= im.cols || v >= im.rows || !(z > 0.0f) || !std::isfinite(x) ||
            !std::isfinite(y) || !std::isfinite(z))
        {
            return;
        }
        f.points.emplace_back(x, y, z);
        f.pixels.push_back({static_cast<uint16_t>(u), static_cast<uint16_t>(v)});
        f.valid.at<uint8_t>(v, u) = 255;
    };

    const bool idxs_ok = obs.points3D_idxs_x.size() == obs.points3D_x.size() &&
                         obs.points3D_idxs_y.size() == obs.points3D_x.size();
    if (obs.hasPoints3D && idxs_ok && !obs.points3D_x.empty())
    {
        for (std::size_t i = 0; i < obs.points3D_x.size(); ++i)
        {
            // Back from MRPT's (+X forward, +Y left, +Z up) to the optical frame.
            add(-obs.points3D_y[i], -obs.points3D_z[i], obs.points3D_x[i], obs.points3D_idxs_x[i],
                obs.points3D_idxs_y[i]);
        }
        return f;
    }

    ASSERTMSG_(obs.hasRangeImage, "3D range scan: 3D points lack pixel indices, no range image");
    const auto& c = obs.cameraParams;
    ASSERTMSG_(
        obs.rangeImage.rows() == im.rows && obs.rangeImage.cols() == im.cols,
        "3D range scan: range and intensity images differ in size");
    const double fx = c.fx(), fy = c.fy(), cx = c.cx(), cy = c.cy();
    for (int v = 0; v < obs.rangeImage.rows(); ++v)
    {
        for (int u = 0; u < obs.rangeImage.cols(); ++u)
        {
            const uint16_t r = obs.rangeImage(v, u);
            if (r == 0)
            {
                continue;
            }
            const double xn = (u - cx) / fx, yn = (v - cy) / fy;
            double z = r * obs.rangeUnits;
            if (!obs.range_is_depth)
            {
                z /= std::sqrt(xn * xn + yn * yn + 1.0);  // range along the ray -> depth
            }
            add(static_cast<float>(xn * z), static_cast<float>(yn * z), static_cast<float>(z), u,
                v);
        }
    }
    return f;
}

}  // namespace emslam::stereo
