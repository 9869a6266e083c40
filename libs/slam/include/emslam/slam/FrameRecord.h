// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <array>
#include <cstddef>
#include <limits>

namespace emslam::slam
{
/** What EntropySlam did on one input frame (the mapper plots it in its
 * report and writes it to stats.csv). \ingroup emslam_slam_grp */
struct FrameRecord
{
    std::size_t index{0};            //!< frame number in the rawlog's stereo / RGB-D stream
    double timestamp{0.0};           //!< [s]
    double ms_stereo{0.0};           //!< stereo front-end (disparity, 3D) [ms]
    double ms_egomotion{0.0};        //!< egomotion, all four stages [ms]
    double ms_rectification{0.0};    //!< time the frame waited for rectification [ms]
    double ms_total{0.0};            //!< the whole frame [ms]
    std::size_t points{0};           //!< 3D points of the frame
    std::size_t initial_matches{0};  //!< matches before LWO
    std::size_t final_matches{0};    //!< matches after LWO
    bool egomotion_ok{true};         //!< false: the step failed (first frame: true)
    bool accepted{false};            //!< joined the trajectory (space sampling)
    double energy{0.0};  //!< map energy after the frame (0 before the first rectification)
    /** Standard deviations of the step from the previous frame, as the
     * odometry prior uses them: δx, δy, δz [m] (translation added) and δθx,
     * δθy, δθz [rad] (rotation R exp(δθ)), camera frame; from the Dpp
     * minimum's curvature, a failed step's wide prediction, or the prior's
     * fixed deviations. NaN for the first frame. */
    std::array<double, 6> step_sigma{
        std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
        std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
        std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
};

}  // namespace emslam::slam
