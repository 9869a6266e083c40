// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Trajectory.h>

namespace emslam::rectify
{
/** True if the trajectory has come back to a place it saw before: two
 * elements put points in the same l_d cell although the path between their
 * frames (summed over the original frames, which a compressed element
 * spans many of) is longer than 2·viewRange() + √3·l_d. Two frames that see
 * one cell are at most that far apart, so a longer path left and came
 * back. Until then the entropy only re-measures what the egomotion
 * measured between neighbouring frames (doc/rectify.md, "Confirming every
 * success before a revisit"). O(points), with the current element poses.
 * \ingroup emslam_rectify_grp \sa TRectifierOptions::confirm_all_before_revisit */
bool revisitsAPlace(const Trajectory& t);

}  // namespace emslam::rectify
