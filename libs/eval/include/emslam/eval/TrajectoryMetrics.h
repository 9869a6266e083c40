// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/eval/SegmentErrors.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::eval
{
/** How an estimated trajectory is aligned to the ground truth before the
 * absolute trajectory error (ATE) is measured.
 * \ingroup emslam_eval_grp \sa alignPositions() */
enum class Alignment
{
    /** No alignment: both trajectories are taken in the same frame. */
    None,
    /** Rigid (rotation + translation), Horn / Umeyama least squares. */
    SE3,
    /** Similarity (rotation + translation + scale), Umeyama 1991. */
    Sim3
};

/** "none" / "se3" / "sim3" (case-insensitive) → Alignment. Throws
 * std::invalid_argument naming the value and the valid ones otherwise.
 * \ingroup emslam_eval_grp */
Alignment parseAlignment(const std::string& s);

/** Alignment → "none" / "se3" / "sim3". \ingroup emslam_eval_grp */
std::string alignmentName(Alignment a);

/** Poses of two trajectories paired by timestamp: `gt[i]` and `est[i]` were
 * taken at (nearly) the same time, in increasing time order.
 * \ingroup emslam_eval_grp \sa associateByTimestamp() */
struct AssociatedPoses
{
    /** Timestamps of each pair [s]. */
    ///@{
    std::vector<double> t_gt, t_est;
    ///@}
    /** T_world_body of the ground truth and T_ref_body of the estimate. */
    ///@{
    std::vector<mrpt::poses::CPose3D> gt, est;
    ///@}

    /** Number of pairs. */
    std::size_t size() const { return gt.size(); }
};

/** Pairs every estimated pose with the ground-truth pose nearest in time, one
 * to one, dropping pairs further apart than `max_dt` [s]. As TUM's
 * associate.py: all candidate pairs within `max_dt` are taken greedily by
 * increasing |dt| (ties: estimate index, then ground-truth time order), so a
 * pose is used at most once even when stamps jitter. The inputs need not be
 * sorted; a negative or NaN `max_dt` pairs nothing.
 * Only neighbouring stamps of the two files are ever candidates (the next
 * pair always joins them): O((N + M) log(N + M)) time and O(N + M) memory
 * however many poses share a stamp or a max_dt window, where listing all
 * candidates takes O(N·M) (bench_association).
 * \ingroup emslam_eval_grp */
AssociatedPoses associateByTimestamp(
    const emslam::io::TumTrajectory& gt, const emslam::io::TumTrajectory& est, double max_dt);

/** A similarity transform p_gt ≈ scale · R · p_est + t, stored as the rigid
 * part `T_gt_est` (R, t) and the `scale`.
 * \ingroup emslam_eval_grp \sa alignPositions() */
struct SimilarityTransform
{
    mrpt::poses::CPose3D T_gt_est;  //!< R and t of p_gt ≈ scale · R · p_est + t
    double scale{1.0};              //!< 1 for a rigid (SE(3)) alignment

    /** The estimated pose `T_ref_body` expressed in the ground-truth frame:
     * rotation R·R_body, position scale·R·p + t. */
    mrpt::poses::CPose3D apply(const mrpt::poses::CPose3D& T_ref_body) const;
    /** Points of the estimate's frame (e.g. its map) in the ground-truth
     * frame: scale·R·p + t. */
    void applyToPoints(std::vector<mrpt::math::TPoint3Df>& points) const;
};

/** Least-squares alignment of the positions `est` onto `gt` (Umeyama,
 * "Least-squares estimation of transformation parameters between two point
 * patterns", PAMI 1991): the identity for Alignment::None, scale fixed to 1 for
 * SE3. A degenerate estimate (all positions equal) keeps scale 1. Throws if
 * the sizes differ or are zero. \ingroup emslam_eval_grp */
SimilarityTransform alignPositions(
    const std::vector<mrpt::poses::CPose3D>& gt,
    const std::vector<mrpt::poses::CPose3D>& est,
    Alignment mode);

/** As alignPositions(), with each pose's orientation too: every pose adds
 * the tips of its three axes `lever_m` out (in the estimate, that length
 * divided by the positions' Sim3 scale). The alignment for what hangs on the
 * poses, such as their map: on a straight path the positions alone leave the
 * rotation about it free, to be set by noise. \ingroup emslam_eval_grp */
SimilarityTransform alignPoses(
    const std::vector<mrpt::poses::CPose3D>& gt,
    const std::vector<mrpt::poses::CPose3D>& est,
    Alignment mode,
    double lever_m = 1.0);

/** Sum of the distances between consecutive positions [m].
 * \ingroup emslam_eval_grp */
double pathLength(const std::vector<mrpt::poses::CPose3D>& poses);

/** Sum of the distances between consecutive poses of `t`, in file order [m].
 * \ingroup emslam_eval_grp */
double pathLength(const emslam::io::TumTrajectory& t);

/** Whether `t` (poses in time order) returns to its start, so that its
 * start-to-end distance is a loop gap: the path is at least LOOP_MIN_PATH_M
 * long and ends within max(LOOP_TOLERANCE_FRACTION of the path,
 * LOOP_TOLERANCE_M) of its first pose. A ground-truth loop ends within a
 * metre or 1 % of its length of the start; a straight 60 m drive ends 60 m
 * away and is no loop. \ingroup emslam_eval_grp */
bool isClosedLoop(const emslam::io::TumTrajectory& t);

/** See isClosedLoop(). */
constexpr double LOOP_MIN_PATH_M = 10.0;
constexpr double LOOP_TOLERANCE_FRACTION = 0.01;
constexpr double LOOP_TOLERANCE_M = 1.0;

/** KITTI-style relative (drift) errors, as the KITTI odometry devkit
 * (evaluate_odometry.cpp) computes them.
 * \ingroup emslam_eval_grp \sa relativeErrors() */
struct RelativeErrors
{
    /** Mean over all segments of |translation error| / segment length [%]. */
    double t_rel_percent{0};
    /** Mean over all segments of rotation error angle / segment length [deg/m]. */
    double r_rel_deg_per_m{0};
    /** Number of segments averaged (0: path too short; the means are then NaN). */
    std::size_t segments{0};
    /** The nominal segment lengths used [m]. */
    std::vector<double> lengths_m;
};

/** The devkit procedure on paired poses: from every `step`-th pose and for
 * every segment length L, the segment ends at the first pose whose
 * ground-truth distance along the path exceeds L; the error is the relative
 * pose inv(inv(E_a)·E_b)·inv(G_a)·G_b, divided by L. The lengths are the
 * devkit's 100, 200, ..., 800 m when the ground-truth path is at least 100 m
 * long, and 10, 20, ..., 50 % of the path otherwise (short excerpts would
 * give no segment at all). Segments that do not fit are skipped.
 * \ingroup emslam_eval_grp */
RelativeErrors relativeErrors(
    const std::vector<mrpt::poses::CPose3D>& gt,
    const std::vector<mrpt::poses::CPose3D>& est,
    std::size_t step = 10);

/** Every figure `emslam-eval` reports for an estimated trajectory against
 * ground truth. Distances are in the ground truth's metres: with
 * Alignment::Sim3 the estimate is scaled first (for every figure), the rigid
 * part of the alignment only changes the ATE.
 * \ingroup emslam_eval_grp \sa EvalApp */
struct TrajectoryMetrics
{
    /** How compute() pairs and aligns the trajectories. */
    struct Options
    {
        Alignment alignment{
            Alignment::SE3};  //!< how the estimate is aligned to the ground truth (Default: se3)
        /** Largest |t_gt - t_est| of an associated pair [s]. (Default: 0.02) */
        double max_dt{0.02};
        /** Relative-error segments start every `segment_step` paired poses.
         * (Default: 10, as the KITTI devkit) */
        std::size_t segment_step{10};
    };

    Alignment alignment{Alignment::SE3};  //!< the alignment used
    /** Poses read from each trajectory. */
    ///@{
    std::size_t gt_poses{0}, est_poses{0};
    ///@}
    /** Pairs found by associateByTimestamp() [`matched_poses`]. */
    std::size_t matched_poses{0};
    /** The alignment applied to the estimate (identity for None). */
    SimilarityTransform align;
    /** The same kind of alignment by alignPoses(): what moves the
     * estimate's map onto the truth's. */
    SimilarityTransform map_align;
    /** RMSE of the position errors after alignment [m] [`ate_rmse_m`]. */
    double ate_rmse_m{0};
    /** KITTI drift, see relativeErrors() [`t_rel_percent`, `r_rel_deg_per_m`]. */
    RelativeErrors rel;
    /** Position error of the last paired pose once the estimate is anchored
     * to the ground truth at the first paired pose, i.e. the drift
     * accumulated from the start [m] [`end_error_m`]. */
    double end_error_m{0};
    /** Distance between the first and the last pose of the whole estimate (in
     * time order, paired or not) [m] [`loop_gap_m`]. */
    double loop_gap_m{0};
    /** Length of the ground-truth path over the paired poses [m] [`path_length_m`]. */
    double path_length_m{0};
    /** Length of the estimated path over the paired poses [m]. */
    double est_path_length_m{0};
    /** Drift per segment length, the lengths chosen by segmentLengthsFor() from
     * the ground-truth path (the report's error-over-distance plot; not in JSON). */
    std::vector<SegmentError> segment_errors;
    /** Per paired pose: ground-truth time since the first pair [s] and position
     * error after alignment [m] (the report's error-over-time plot; not in JSON). */
    ///@{
    std::vector<double> error_time_s, position_error_m;
    ///@}

    /** Associates, aligns and measures. Throws std::runtime_error if either
     * trajectory is empty or no pose pairs within `opts.max_dt`. */
    static TrajectoryMetrics compute(
        const emslam::io::TumTrajectory& gt,
        const emslam::io::TumTrajectory& est,
        const Options& opts);

    /** One JSON object with the keys in brackets above plus `alignment`,
     * `scale`, `gt_poses`, `est_poses`, `segments`, `segment_lengths_m`,
     * `est_path_length_m`; NaN is written as null. */
    std::string toJson() const;
};

}  // namespace emslam::eval
