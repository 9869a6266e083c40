// SPDX-License-Identifier: BSD-3-Clause
// Private to emslam_io (not installed): shared by the stereo dataset readers.
#pragma once

#include <mrpt/img/TStereoCamera.h>
#include <mrpt/obs/CObservationStereoImages.h>

#include <string>

namespace emslam::io
{
/** One stereo pair of a dataset folder as the observation emslam-import
 * writes (the caller sets its label and time): both images (as stored),
 * `hasImageRight`, the calibration `calib`, the camera at the robot's
 * origin. Throws, naming the file, if an image cannot be read or its size is
 * not `calib`'s (`size_source` says where that size came from); the size is
 * read from the image headers before decoding (loadImageFile()). */
mrpt::obs::CObservationStereoImages::Ptr loadStereoPairObservation(
    const std::string& left_file,
    const std::string& right_file,
    const mrpt::img::TStereoCamera& calib,
    const std::string& size_source);

}  // namespace emslam::io
