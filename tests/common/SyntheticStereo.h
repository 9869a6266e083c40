// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/stereo/StereoFrame.h>

#include <mrpt/img/TStereoCamera.h>

#include <cstdint>
#include <opencv2/core.hpp>

namespace emslam::test
{
/** An ideal rectified stereo camera: no distortion, shared intrinsics, the
 * right camera `baseline` metres along +x. */
mrpt::img::TStereoCamera idealStereoCamera(int width, int height, double f, double baseline);

/** A rectified pair of a textured fronto-parallel plane at depth `z` seen by
 * `cam`: the texture is a smooth random function (seeded) evaluated at exact
 * sub-pixel coordinates, so the right image is the left one shifted by the
 * true disparity f*B/z without resampling error. */
void renderFrontoParallelPlane(
    const mrpt::img::TStereoCamera& cam,
    double z,
    std::uint32_t seed,
    cv::Mat& left,
    cv::Mat& right);

/** A frame with this intensity image whose every pixel has a point on a
 * fronto-parallel plane 5 m ahead, 1 cm apart (no stereo involved). */
emslam::stereo::StereoFrame frameWithImage(const cv::Mat& img);

/** Uniform 8-bit noise, seeded: a texture every feature of which is unique. */
cv::Mat noiseImage(int w, int h, unsigned seed);

}  // namespace emslam::test
