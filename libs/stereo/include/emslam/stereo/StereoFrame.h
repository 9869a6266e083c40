// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/img/TStereoCamera.h>
#include <mrpt/math/TPoint3D.h>

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace emslam::stereo
{
/** Pixel coordinates of a 3D point in the reference image (column, row).
 * \ingroup emslam_stereo_grp */
struct PixelCoord
{
    std::uint16_t u{0};  //!< column [px]
    std::uint16_t v{0};  //!< row [px]
};

/** One observation as the rest of emslam sees it: the reference (left)
 * intensity image plus the semi-dense 3D cloud reconstructed from stereo (or
 * given by an RGB-D camera).
 *
 * Points are in the **left camera frame** (x right, y down, z forward, metres);
 * `points[i]` is seen at pixel `pixels[i]` of `intensity`. `valid` marks the
 * pixels that have a point (255) and those that do not (0). `camera` is the
 * calibration of the images as stored here, i.e. rectified and scaled.
 * \ingroup emslam_stereo_grp \sa StereoFrontEnd, toRangeScan, fromRangeScan */
struct StereoFrame
{
    /** Shared pointer to a frame. */
    using Ptr = std::shared_ptr<StereoFrame>;

    mrpt::Clock::time_point timestamp{};  //!< acquisition time of the pair
    std::string sensor_label;             //!< the sensor's label (CObservation::sensorLabel)

    /** Reference intensity image, CV_8UC1. */
    cv::Mat intensity;
    /** Validity mask, CV_8UC1, same size as `intensity` (255: has a point). */
    cv::Mat valid;
    /** Disparity of every valid pixel [px], CV_32FC1 (0 where invalid); empty for RGB-D input. */
    cv::Mat disparity;

    std::vector<mrpt::math::TPoint3Df> points;  //!< 3D points, left camera frame [m]
    std::vector<PixelCoord> pixels;             //!< pixel of `intensity` where each point is seen

    /** Calibration of `intensity` (rectified, scaled). For RGB-D input only
     * the left camera is meaningful and the baseline is zero. */
    mrpt::img::TStereoCamera camera;

    /** Number of points. */
    std::size_t size() const { return points.size(); }
    /** No point. */
    bool empty() const { return points.empty(); }
    /** Fraction of the image pixels that have a 3D point, in [0,1]. */
    double density() const;
};

}  // namespace emslam::stereo
