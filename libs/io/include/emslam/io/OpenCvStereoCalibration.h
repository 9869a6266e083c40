// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/img/TStereoCamera.h>

#include <cstddef>
#include <string>

namespace emslam::io
{
/** Reads an OpenCV stereo calibration (cv::FileStorage: YAML, XML or JSON),
 * the layout that OpenCV's `stereo_calib` sample and most calibration
 * scripts write from cv::stereoCalibrate():
 * \code
 *   M1, M2   (or K1, K2)   3x3 camera matrices of the left and right cameras
 *   D1, D2                 distortion (k1 k2 p1 p2 [k3 [k4 k5 k6]]), may be empty
 *   R                      3x3 rotation (or a 3x1 Rodrigues vector) and
 *   T                      3x1 translation: X_right = R * X_left + T
 *   image_width, image_height   (or image_size / imageSize = [w, h]): optional
 * \endcode
 * `extrinsics_file`, if not empty, is read too (the sample writes M/D to
 * `intrinsics.yml` and R/T to `extrinsics.yml`): each key is taken from the
 * first file that has it. T is multiplied by `translation_scale` (0.001 for a
 * calibration made with the pattern's squares in millimetres), so that the
 * result's `rightCameraPose` (the right camera in the left camera's frame,
 * rotation R^T and position -R^T T) is in metres. The cameras are raw (as
 * calibrated, before rectification). Without an image size the result has a
 * 0x0 resolution: the caller fills it in (e.g. from the video).
 *
 * Files over MAX_OPENCV_CALIBRATION_BYTES, with NUL bytes or nesting deeper
 * than MAX_OPENCV_CALIBRATION_NESTING (brackets or indentation: OpenCV's
 * parser recurses on it) are refused before parsing. Throws std::runtime_error naming the file and
 * the key on a missing file or key, a matrix of the wrong size, non-finite numbers, or a distortion
 * model other than OpenCV's 4/5/8 coefficients. \ingroup emslam_io_grp \sa
 * saveOpenCvStereoCalibration */
mrpt::img::TStereoCamera loadOpenCvStereoCalibration(
    const std::string& file,
    const std::string& extrinsics_file = {},
    double translation_scale = 1.0);

/** Writes `cam` in the layout loadOpenCvStereoCalibration() reads (M1, D1,
 * M2, D2, R, T in metres, image_width, image_height), through
 * cv::FileStorage (the format follows the extension: .yml/.yaml, .xml,
 * .json). Throws naming the file if it cannot be written.
 * \ingroup emslam_io_grp */
void saveOpenCvStereoCalibration(const std::string& file, const mrpt::img::TStereoCamera& cam);

/** True if `file`'s extension is one cv::FileStorage reads: .yml, .yaml,
 * .xml or .json (any case). */
bool isOpenCvStorageFile(const std::string& file);

/** Largest calibration file accepted [bytes]; real ones are under 4 KiB. */
constexpr std::size_t MAX_OPENCV_CALIBRATION_BYTES = std::size_t{1} << 16;
/** Deepest bracket or indentation nesting accepted (a calibration has 2). */
constexpr int MAX_OPENCV_CALIBRATION_NESTING = 16;

}  // namespace emslam::io
