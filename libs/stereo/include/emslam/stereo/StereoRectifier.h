// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/img/TStereoCamera.h>

#include <opencv2/core.hpp>

namespace emslam::stereo
{
/** Undistorts and rectifies raw stereo pairs so that epipolar lines are image
 * rows. The remap tables are built once per calibration and cached; a
 * calibration that is already rectified (no distortion, equal fx, fy, cy; cx may differ,
 * right camera on the left camera's x axis) makes rectify() a no-op copy.
 *
 * The rectified calibration (rectifiedCamera()) has no distortion, shared
 * intrinsics and the right camera at (baseline, 0, 0).
 * \ingroup emslam_stereo_grp */
class StereoRectifier
{
public:
    StereoRectifier() = default;
    /** Prepares the maps for `raw`. `alpha` is OpenCV's free scaling parameter
     * (0: only valid pixels, 1: all source pixels kept). */
    explicit StereoRectifier(const mrpt::img::TStereoCamera& raw, double alpha = 0.0);

    /** (Re)builds the maps only if `raw` differs from the cached calibration. */
    void setCalibration(const mrpt::img::TStereoCamera& raw, double alpha = 0.0);

    /** True once a calibration was set. */
    bool isInitialized() const { return m_initialized; }
    /** True when the input calibration is already rectified. */
    bool isIdentity() const { return m_identity; }

    /** Rectifies a raw pair; images must have the calibration's size. */
    void rectify(
        const cv::Mat& raw_left,
        const cv::Mat& raw_right,
        cv::Mat& rect_left,
        cv::Mat& rect_right) const;

    /** The calibration given (setCalibration()). */
    const mrpt::img::TStereoCamera& rawCamera() const { return m_raw; }
    /** The calibration of the rectified pair. */
    const mrpt::img::TStereoCamera& rectifiedCamera() const { return m_rectified; }

    /** True if `cam` needs no rectification: no distortion, equal fx, fy and cy, the
     * right camera on the left one's +x axis (tolerances of 1e-6 relative). */
    static bool isAlreadyRectified(const mrpt::img::TStereoCamera& cam);

private:
    bool m_initialized{false};
    bool m_identity{false};
    double m_alpha{0.0};
    mrpt::img::TStereoCamera m_raw, m_rectified;
    cv::Mat m_map_left_x, m_map_left_y, m_map_right_x, m_map_right_y;
};

}  // namespace emslam::stereo
