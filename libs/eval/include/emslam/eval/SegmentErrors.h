// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <vector>

namespace emslam::eval
{
/** The drift over one segment length, averaged over every segment of that
 * length (one point of the KITTI devkit's "error over path length" plot).
 * \ingroup emslam_eval_grp \sa segmentErrors() */
struct SegmentError
{
    /** Nominal segment length [m]. */
    double length_m{0};
    /** Mean |translation error| / length [%] (NaN when `segments` is 0). */
    double t_err_percent{0};
    /** Mean rotation error angle / length [deg/m] (NaN when `segments` is 0). */
    double r_err_deg_per_m{0};
    /** Number of segments of this length that fit in the path. */
    std::size_t segments{0};
};

/** Segment lengths that suit a path of `path_length_m` metres: eight
 * multiples 1..8 of a step, the largest 1, 2 or 5 x 10^k metres not above
 * 1/20 of the path, capped at 100 m. Paths of 2 km or more get the KITTI
 * devkit's 100, 200, ..., 800 m; shorter runs keep eight segment lengths
 * spread over their first 40 % (a 104 m loop: 5, 10, ..., 40 m; a 60 m drive:
 * 2, 4, ..., 16 m), so every run gets an error-over-distance curve. Empty for
 * a path without length. \ingroup emslam_eval_grp */
std::vector<double> segmentLengthsFor(double path_length_m);

/** The KITTI devkit's relative errors per segment length, on poses already
 * paired (gt[i] with est[i]) and aligned: from every `step`-th pose and for
 * every length L, the segment ends at the first pose whose ground-truth
 * distance along the path exceeds L; its error is the relative pose
 * inv(inv(E_a)·E_b)·inv(G_a)·G_b, divided by L. Lengths that fit nowhere
 * get `segments` = 0. Throws std::invalid_argument if the sizes differ.
 * \ingroup emslam_eval_grp */
std::vector<SegmentError> segmentErrors(
    const std::vector<mrpt::poses::CPose3D>& gt,
    const std::vector<mrpt::poses::CPose3D>& est,
    const std::vector<double>& lengths_m,
    std::size_t step = 10);

}  // namespace emslam::eval
