// SPDX-License-Identifier: BSD-3-Clause
// Private to emslam_stereo (not installed): shared by the stereo matchers and
// the front-end.
#pragma once

#include <opencv2/core.hpp>

namespace emslam::stereo
{
/** `im` itself if it has one channel, else its grey levels (BGR or BGRA). */
cv::Mat grayImage(const cv::Mat& im);

}  // namespace emslam::stereo
