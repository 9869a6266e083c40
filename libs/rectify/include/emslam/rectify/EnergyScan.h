// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Trajectory.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::rectify
{
/** What scanEnergy() scans. Translation offsets are ±k·step for k = 1..K, and
 * so are rotation offsets. \ingroup emslam_rectify_grp \sa scanEnergy() */
struct EnergyScanOptions
{
    /** Throws std::invalid_argument naming the field if a value is invalid. */
    void validate() const;

    /** About this many actions are scanned, spread evenly over a_1..a_{N-1}
     * (a_1 and a_{N-1} included); the middle a_{N/2} is added if the spread
     * misses it, and a_0 too when the energy depends on the global alignment
     * (the rectifier then perturbs it). (Default: 7) */
    std::size_t actions{7};
    /** Translation step [m]; 0: a quarter of the cell size l_d. (Default: 0) */
    double translation_step_m{0.0};
    /** Translation offsets per side K (≥ 1). (Default: 8, i.e. ±2 l_d) */
    int translation_steps{8};
    /** Rotation step [deg]. (Default: 1.0) */
    double rotation_step_deg{1.0};
    /** Rotation offsets per side K (≥ 1). (Default: 6, i.e. ±6°) */
    int rotation_steps{6};
    /** Grid phases of the entropy (as Trajectory::setGridPhases(), 1..8);
     * 0: the trajectory's own, the energy its rectifier minimises. (Default: 0) */
    int grid_phases{0};
};

/** The energy along one dimension of one action, around the truth: a_k
 * perturbed by each offset (perturbAction(), as the rectifier does), every
 * other action the truth's. \ingroup emslam_rectify_grp */
struct EnergyScanLine
{
    /** k: the action perturbed; elements k..N-1 move. */
    std::size_t action{0};
    /** 0..5: δx, δy, δz, δθx, δθy, δθz (actionDimensionName()). */
    int dimension{0};
    /** Offsets, ascending, 0 (the truth) included [m, or rad for a rotation]. */
    std::vector<double> offsets;
    /** Entropy at each offset [nats]. */
    std::vector<double> energies;
    /** E(0), the entropy of the true map [nats]. */
    double energy_at_truth{0};
    /** The offset of the lowest energy (on a tie, the one nearest 0). */
    double argmin_offset{0};
    /** The lowest energy [nats]. */
    double min_energy{0};
    /** (E(+s) + E(−s) − 2 E(0)) / s² for the smallest step s [nats per m², or per rad²]. */
    double curvature{0};
    /** (E(+s) − E(−s)) / 2s for the smallest step s [nats per m, or per rad]. */
    double slope{0};

    /** True for δθx, δθy, δθz (offsets in rad). */
    bool isRotation() const { return dimension >= 3; }
    /** True if the truth is the minimum along this line. */
    bool truthIsMinimum() const { return argmin_offset == 0.0; }
};

/** One dimension's lines, summarised. */
struct EnergyScanDimension
{
    int dimension{0};      //!< 0..5, as EnergyScanLine::dimension
    std::size_t lines{0};  //!< lines scanned along it
    /** Fraction of the lines whose minimum is at the truth. */
    double fraction_at_truth{0};
    /** Median |argmin offset| [m, or rad]. */
    double median_abs_argmin{0};
    /** Median curvature at the truth [nats per m², or per rad²]. */
    double median_curvature{0};
};

/** The aggregate of a scan; NaN where there were no lines. */
struct EnergyScanSummary
{
    std::size_t lines{0};           //!< lines scanned
    std::size_t lines_at_truth{0};  //!< lines whose minimum is at the truth
    std::size_t evaluations{0};     //!< energies computed (offset 0 once)
    std::size_t elements{0};        //!< N
    int grid_phases{1};             //!< grid phases of the scanned entropy
    double energy_at_truth{0};      //!< [nats]
    /** Fraction of all lines whose minimum is at the truth. */
    double fraction_at_truth{0};
    /** Median |argmin offset| over the translation lines [m] and over the
     * rotation lines [rad]. */
    ///@{
    double median_abs_argmin_translation_m{0};
    double median_abs_argmin_rotation_rad{0};
    ///@}
    /** Per scanned dimension, in order. */
    std::vector<EnergyScanDimension> dimensions;
    double seconds{0};  //!< wall time of the scan [s]
};

/** A whole scan: one line per (action, dimension), actions ascending. */
struct EnergyScan
{
    std::vector<EnergyScanLine> lines;  //!< one per (action, dimension), actions ascending
    EnergyScanSummary summary;          //!< their aggregate
};

/** "x", "y", "z", "theta_x", "theta_y", "theta_z" for dimensions 0..5.
 * \ingroup emslam_rectify_grp */
std::string actionDimensionName(int dimension);

/** The dimensions a `dof` energy perturbs: 3DOF {δx, δz, δθ_y} = {0, 2, 4},
 * 6DOF all six. \ingroup emslam_rectify_grp */
std::vector<int> actionDimensions(int dof);

/** The actions scanEnergy() scans in `t` (see EnergyScanOptions::actions),
 * ascending. \ingroup emslam_rectify_grp */
std::vector<std::size_t> energyScanActions(const Trajectory& t, std::size_t count);

/** Scans the entropy of `t`'s simplified observations around the truth:
 * with `truth_poses` (one per element, e.g. from elementPosesAt()) the
 * actions are the truth's, and each selected action is perturbed alone by
 * each offset along each dimension of t.dof(); the elements' poses follow
 * by composing the actions. The map is built once at the truth and only the
 * moved segment is re-binned, then reverted, per offset. The energy is the
 * paper's entropy of t's energy type (no odometry prior), averaged over the
 * grid phases when there are several; E(0) is exactly
 * entropyAtElementPoses(t, truth_poses, phases). `t` does not change.
 * Throws std::invalid_argument on bad options or a pose count that is not
 * t.size(). \ingroup emslam_rectify_grp \sa entropyAtElementPoses() */
EnergyScan scanEnergy(
    const Trajectory& t,
    const std::vector<mrpt::poses::CPose3D>& truth_poses,
    const EnergyScanOptions& options = {});

}  // namespace emslam::rectify
