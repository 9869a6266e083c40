// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/img/TStereoCamera.h>

#include <string>

namespace emslam::io
{
/** Reads a KITTI odometry `calib.txt`: the `P0:` (left) and `P1:` (right)
 * 3x4 row-major projection matrices of the rectified pair. Other lines (P2,
 * P3, Tr, ...) are ignored; CRLF line ends are tolerated. Image size is not in
 * the file: pass it (both cameras get it).
 * The result has no distortion, identical intrinsics and the right camera at
 * (baseline, 0, 0) in the left frame, baseline = -P1[0,3] / fx.
 * Throws, naming the file and the line, on a missing file, a missing P0/P1,
 * or a garbled matrix.
 * \ingroup emslam_io_grp */
mrpt::img::TStereoCamera loadKittiCalibration(
    const std::string& calib_txt, unsigned int image_width, unsigned int image_height);

/** Reads an EuRoC (ASL) camera pair: `cam0/sensor.yaml` (left) and
 * `cam1/sensor.yaml` (right) with `resolution`, `intrinsics: [fu, fv, cu, cv]`,
 * `distortion_model: radial-tangential`, `distortion_coefficients: [k1 k2 p1 p2]`
 * and `T_BS` (camera in body frame, 4x4 row-major). The right camera's pose in
 * the left camera frame is `inv(T_BS_left) * T_BS_right`. The cameras are raw
 * (distorted, not rectified). The files are read by EurocSensorYaml (strict,
 * at most 1 MiB). Throws, naming the file, the line and the key, on a missing
 * file, malformed YAML, a missing key, or malformed numbers.
 * \ingroup emslam_io_grp \sa EurocSensorYaml */
mrpt::img::TStereoCamera loadEurocCalibration(
    const std::string& cam0_sensor_yaml, const std::string& cam1_sensor_yaml);

/** Reads MRPT's TStereoCamera INI form (see
 * stereo::loadStereoCameraFromConfig()) from `ini_file`, read by
 * readIniFile() (at most MAX_INI_BYTES, no repeated section or key). Throws
 * naming the file if it does not exist or the calibration is unusable.
 * \ingroup emslam_io_grp */
mrpt::img::TStereoCamera loadStereoCameraFromIniFile(
    const std::string& ini_file, const std::string& section);

}  // namespace emslam::io
