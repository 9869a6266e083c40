// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/math/TPoint3D.h>

#include <cstdint>
#include <vector>

namespace emslam::egomotion
{
/** A gradient-local-maximum (GLM) feature: a pixel of the reference image
 * whose gradient magnitude is a strict local maximum in its window, with the
 * stereo 3D point seen there (left camera frame, metres).
 * \ingroup emslam_egomotion_grp */
struct Feature
{
    /** Pixel (column, row). */
    ///@{
    std::uint16_t u{0}, v{0};
    ///@}
    mrpt::math::TPoint3Df point;  //!< 3D point, left camera frame [m]
    float gradient_angle{0};      //!< atan2(Iy, Ix) [rad], in (-pi, pi]
    float gradient_magnitude{0};  //!< |grad I| (Sobel units)
};

/** Features of one image, in the order of its 3D points. */
using FeatureList = std::vector<Feature>;

/** A putative correspondence: feature `prev` of the previous frame matches
 * feature `cur` of the current one with similarity S = |rho| in [0, 1].
 * \ingroup emslam_egomotion_grp */
struct Match
{
    int prev{-1};         //!< index of the feature in the previous frame's list
    int cur{-1};          //!< index of the feature in the current frame's list
    float similarity{0};  //!< S = |rho|, in [0, 1]
};

using MatchList = std::vector<Match>;

}  // namespace emslam::egomotion
