// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/math/TPoint3D.h>

#include <vector>

namespace emslam::egomotion
{
/** Result of leaving-the-worst-out. \ingroup emslam_egomotion_grp */
struct LwoResult
{
    std::vector<int> kept;  //!< indices (into the input pairs) that survive
    int iterations{0};      //!< matches removed
    double final_sigma{0};  //!< std. dev. of the D_ij of the survivors
};

/** Stage 3 of §2.1: structural refinement. `a[i]` (previous frame) and `b[i]`
 * (current frame) are the 3D points of match i. D_ijkl (Eq. 2) compares the
 * segment lengths |a_i a_k| and |b_i b_k|; D_i (Eq. 3) averages it over the
 * other matches. Each iteration removes the match with the largest D_i, until
 * the standard deviation of the D_i is <= sigma_min (or fewer than 3 remain).
 * Cost: O(M^2) once, then O(M) per iteration (running sums).
 * \ingroup emslam_egomotion_grp */
LwoResult refineLwo(
    const std::vector<mrpt::math::TPoint3Df>& a,
    const std::vector<mrpt::math::TPoint3Df>& b,
    double sigma_min);

}  // namespace emslam::egomotion
