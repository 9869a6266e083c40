// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include <vector>

namespace emslam::egomotion
{
/** Polishes an action by the stereo reprojection error, not in the paper:
 * each matched point of one frame is moved by the action into the other
 * frame's camera and compared there with its match in image coordinates,
 * (x/z, y/z) and the disparity B/z, in both directions. On real images a
 * feature is located to a pixel or two across frames while its disparity
 * is good to a fraction of one; Dpp (Eq. 7) trusts the bearings and
 * discounts the depths, this fit weighs each coordinate by its own noise.
 * That noise is read from the data (robust deviation of the residuals);
 * each residual's covariance adds the moved point's own noise carried
 * through the motion; Huber's loss per whitened coordinate. Levenberg-
 * Marquardt from a given pose (the Dpp's).
 * \ingroup emslam_egomotion_grp */
class StereoReprojectionRefinement
{
public:
    /** The refined pose, its residuals and covariance. */
    struct Result
    {
        mrpt::poses::CPose3D
            T_prev_cur;            //!< refined pose of the current camera in the previous one
        double rms_initial_px{0};  //!< RMS residual at the start [px]
        double rms_final_px{0};    //!< RMS residual at the end [px]
        int evaluations{0};        //!< cost evaluations (with or without its Jacobian)
        std::size_t pairs{0};      //!< pairs used (finite, in front of both cameras)
        /** Covariance of T_prev_cur, [x, y, z, θx, θy, θz] with the rotation
         * perturbed on the right (as DppPoseEstimator::Result::covariance),
         * from the whitened residuals. Valid only if has_covariance. */
        mrpt::math::CMatrixDouble66 covariance;
        bool has_covariance{false};  //!< false: `covariance` is not valid
    };

    /** `a` in the previous left-camera frame, `b` in the current one (x right,
     * y down, z forward [m]), `baseline` the stereo baseline [m] (> 0),
     * `focal_px` the focal length [px] (only scales the reported residuals).
     * Needs ≥ 4 usable pairs, else returns `T_prev_cur` unchanged. */
    static Result refine(
        const std::vector<mrpt::math::TPoint3Df>& a,
        const std::vector<mrpt::math::TPoint3Df>& b,
        const mrpt::poses::CPose3D& T_prev_cur,
        double baseline,
        double focal_px,
        int max_iterations = 50,
        double tolerance = 1e-7);
};

}  // namespace emslam::egomotion
