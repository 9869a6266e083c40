// SPDX-License-Identifier: BSD-3-Clause
// Private to emslam_io (not installed): shared by the dataset readers.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace emslam::io
{
/** Reads an image file as stored (`cv::IMREAD_UNCHANGED`: depth and channels
 * kept). Throws, naming the file, if it does not exist or is not a readable
 * image. Used by KittiSequence, EurocSequence and TumRgbdSequence. */
cv::Mat loadImageFile(const std::string& file);

}  // namespace emslam::io
