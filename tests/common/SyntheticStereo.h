// SPDX-License-Identifier: BSD-3-Clause
#pragma once

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

}  // namespace emslam::test
