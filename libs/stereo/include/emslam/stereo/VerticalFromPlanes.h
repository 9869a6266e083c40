// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/stereo/StereoFrame.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPoint3D.h>

#include <cstddef>
#include <optional>
#include <string>

namespace emslam::stereo
{
/** The up direction one stereo frame sees, in its camera frame, with its
 * covariance (rank 2: only the direction is measured). */
struct VerticalMeasurement
{
    mrpt::math::TVector3D up{0, -1, 0};      //!< unit vector, camera frame (y down)
    mrpt::math::CMatrixDouble33 covariance;  //!< of `up` [rad²], orthogonal to it
    std::size_t patches{0};                  //!< horizontal patches that made it
    double dispersion{1};                    //!< scatter of the patches / their own noise

    /** The inverse of `covariance` on the plane orthogonal to `up` (zero
     * along `up`), for a weighted residual of the direction. */
    mrpt::math::CMatrixDouble33 information() const;
};

/** Measures the vertical in one stereo frame from its horizontal planes
 * (floors, ceilings, table tops, stair treads): the frame's disparity image
 * is cut into square patches, a plane d = a·u + b·v + c is fitted to each
 * (a plane in space is a plane in disparity), its normal and the normal's
 * covariance follow from the fit's residual, and the normals within
 * `max_angle_deg` of the predicted up are fused by their information.
 *
 * Why: on a walker the egomotion's small pitch and roll errors of a
 * staircase tilt a whole floor, and no loop sees it (the floors meet only
 * at the stairs). A building's floors are level; each keyframe that sees a
 * floor says where up is, with an uncertainty from its own data. The patch
 * scatter beyond their own noise (`dispersion`, from stereo's correlated
 * errors) widens the covariance, never narrows it.
 *
 * Returns nothing for a frame without a disparity image (RGB-D) or with
 * fewer than `min_patches` horizontal patches.
 * \ingroup emslam_stereo_grp \sa emslam::slam::LoopCloser */
class VerticalFromPlanes
{
public:
    /** `[VerticalFromPlanes]` parameters (the mapper loads them beside `[LoopCloser]`). */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of a bad value. */
        void validate() const;

        /** [px] side of the square patches. (Default: 16) */
        int patch_px{16};
        /** [deg] a patch whose normal is farther from the predicted up is
         * a wall or a slope. (Default: 20) */
        double max_angle_deg{20.0};
        /** Fewer horizontal patches: no measurement. (Default: 8) */
        int min_patches{8};
    };

    /** A measurement with the parameters `p` (validated). */
    explicit VerticalFromPlanes(const TParameters& p);

    /** The up direction of `f` near `predicted_up` (camera frame, any
     * length > 0), or nothing. */
    std::optional<VerticalMeasurement> measure(
        const StereoFrame& f, const mrpt::math::TVector3D& predicted_up) const;

private:
    TParameters m_p;
};

}  // namespace emslam::stereo
