// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/img/TStereoCamera.h>

namespace emslam::slam
{
/** The depth uncertainty of a stereo (or RGB-D) point: a disparity error of
 * σ_d pixels moves a point at depth z by σ_z = z² σ_d / (f b) along its
 * viewing ray (f the focal length [px], b the baseline [m]), so a point
 * twice as far is four times less certain. Without a baseline (RGB-D input,
 * whose depth comes from the sensor) the same quadratic law is used with a
 * sensor coefficient: σ_z = k z² (a Kinect-class sensor: k ≈ 1.5·10⁻³ m⁻¹,
 * Khoshelham & Elberink, Sensors 2012).
 * \ingroup emslam_slam_grp \sa FusedPointCloud */
class DepthNoiseModel
{
public:
    /** `sigma_disparity_px`: σ_d [px]; `rgbd_coefficient`: k [1/m], used
     * when the camera has no baseline. */
    DepthNoiseModel(
        const mrpt::img::TStereoCamera& camera, double sigma_disparity_px, double rgbd_coefficient);

    /** σ_z [m] of a point at depth `z` [m] (along the optical axis). */
    double sigmaAt(double z) const { return m_k * z * z; }
    /** The coefficient k of σ_z = k z² [1/m]: σ_d / (f b), or the RGB-D one. */
    double coefficient() const { return m_k; }

private:
    double m_k;
};

}  // namespace emslam::slam
