// SPDX-License-Identifier: BSD-3-Clause
#include "SyntheticStereo.h"

#include <cmath>
#include <random>
#include <vector>

namespace emslam::test
{
mrpt::img::TStereoCamera idealStereoCamera(int width, int height, double f, double baseline)
{
    mrpt::img::TStereoCamera c;
    c.leftCamera.ncols = width;
    c.leftCamera.nrows = height;
    c.leftCamera.setIntrinsicParamsFromValues(f, f, (width - 1) / 2.0, (height - 1) / 2.0);
    c.leftCamera.dist.fill(0);
    c.rightCamera = c.leftCamera;
    c.rightCameraPose = mrpt::math::TPose3DQuat(baseline, 0, 0, 1, 0, 0, 0);
    return c;
}

void renderFrontoParallelPlane(
    const mrpt::img::TStereoCamera& cam,
    double z,
    std::uint32_t seed,
    cv::Mat& left,
    cv::Mat& right)
{
    const int w = static_cast<int>(cam.leftCamera.ncols);
    const int h = static_cast<int>(cam.leftCamera.nrows);
    const double disparity = cam.leftCamera.fx() * cam.rightCameraPose.x / z;

    // Random grid, 2.5 px per cell, bilinearly interpolated: smooth enough for
    // sub-pixel disparity, textured enough for matching.
    constexpr double CELL = 2.5;
    const int gw = static_cast<int>((w + disparity) / CELL) + 4,
              gh = static_cast<int>(h / CELL) + 4;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(20.0, 235.0);
    std::vector<double> grid(static_cast<std::size_t>(gw) * gh);
    for (auto& g : grid)
    {
        g = U(rng);
    }
    auto texture = [&](double x, double y)
    {
        const double gx = x / CELL + 1, gy = y / CELL + 1;
        const int ix = static_cast<int>(std::floor(gx)), iy = static_cast<int>(std::floor(gy));
        const double fx = gx - ix, fy = gy - iy;
        auto at = [&](int a, int b) { return grid[static_cast<std::size_t>(b) * gw + a]; };
        return (1 - fy) * ((1 - fx) * at(ix, iy) + fx * at(ix + 1, iy)) +
               fy * ((1 - fx) * at(ix, iy + 1) + fx * at(ix + 1, iy + 1));
    };
    left.create(h, w, CV_8UC1);
    right.create(h, w, CV_8UC1);
    for (int v = 0; v < h; ++v)
    {
        for (int u = 0; u < w; ++u)
        {
            // A point seen at u in the right image is at u + d in the left one.
            left.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(texture(u, v));
            right.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(texture(u + disparity, v));
        }
    }
}

emslam::stereo::StereoFrame frameWithImage(const cv::Mat& img)
{
    emslam::stereo::StereoFrame f;
    f.intensity = img;
    f.valid = cv::Mat(img.size(), CV_8UC1, cv::Scalar(255));
    for (int v = 0; v < img.rows; ++v)
    {
        for (int u = 0; u < img.cols; ++u)
        {
            f.points.emplace_back((u - img.cols / 2) * 0.01f, (v - img.rows / 2) * 0.01f, 5.0f);
            f.pixels.push_back({static_cast<std::uint16_t>(u), static_cast<std::uint16_t>(v)});
        }
    }
    return f;
}

cv::Mat noiseImage(int w, int h, unsigned seed)
{
    cv::Mat img(h, w, CV_8UC1);
    cv::RNG rng(seed);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    return img;
}

}  // namespace emslam::test
