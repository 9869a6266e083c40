// SPDX-License-Identifier: BSD-3-Clause
#include "GrayImage.h"

#include <opencv2/imgproc.hpp>

namespace emslam::stereo
{
cv::Mat grayImage(const cv::Mat& im)
{
    if (im.channels() == 1)
    {
        return im;
    }
    cv::Mat g;
    cv::cvtColor(im, g, im.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
    return g;
}

}  // namespace emslam::stereo
