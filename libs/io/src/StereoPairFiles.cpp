// SPDX-License-Identifier: BSD-3-Clause
#include "StereoPairFiles.h"

#include "ImageFile.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <utility>

namespace emslam::io
{
mrpt::obs::CObservationStereoImages::Ptr loadStereoPairObservation(
    const std::string& left_file,
    const std::string& right_file,
    const mrpt::img::TStereoCamera& calib,
    const std::string& size_source)
{
    const cv::Mat left = loadImageFile(left_file);
    const cv::Mat right = loadImageFile(right_file);
    const unsigned int width = calib.leftCamera.ncols, height = calib.leftCamera.nrows;
    for (const auto& [im, file] : {std::pair{&left, &left_file}, std::pair{&right, &right_file}})
    {
        if (static_cast<unsigned int>(im->cols) != width ||
            static_cast<unsigned int>(im->rows) != height)
        {
            THROW_EXCEPTION_FMT(
                "Image size mismatch: '%s' is %dx%d, expected %ux%u (%s)", file->c_str(), im->cols,
                im->rows, width, height, size_source.c_str());
        }
    }
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
