// SPDX-License-Identifier: BSD-3-Clause
#include "StereoPairFiles.h"

#include <emslam/io/ImageFile.h>

#include <mrpt/poses/CPose3DQuat.h>

namespace emslam::io
{
mrpt::obs::CObservationStereoImages::Ptr loadStereoPairObservation(
    const std::string& left_file,
    const std::string& right_file,
    const mrpt::img::TStereoCamera& calib,
    const std::string& size_source)
{
    // The calibration's size comes from validated files; checked before decoding.
    const cv::Size size(
        static_cast<int>(calib.leftCamera.ncols), static_cast<int>(calib.leftCamera.nrows));
    const cv::Mat left = loadImageFile(left_file, size, size_source);
    const cv::Mat right = loadImageFile(right_file, size, size_source);
    auto obs = mrpt::obs::CObservationStereoImages::Create();
    obs->imageLeft = mrpt::img::CImage(left, mrpt::img::SHALLOW_COPY);
    obs->imageRight = mrpt::img::CImage(right, mrpt::img::SHALLOW_COPY);
    obs->hasImageRight = true;
    obs->hasImageDisparity = false;
    obs->setStereoCameraParams(calib);
    obs->cameraPose = mrpt::poses::CPose3DQuat();
    return obs;
}

}  // namespace emslam::io
