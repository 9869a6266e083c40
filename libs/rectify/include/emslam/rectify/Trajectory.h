// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/maps/WeightedPointCloud.h>
#include <emslam/rectify/OdometryPrior.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

namespace emslam::rectify
{
/** One original (accepted) frame inside a trajectory element: after
 * compression an element stands for several frames. */
struct ElementFrame
{
    double timestamp{0.0};                                             //!< [s]
    std::size_t frame_index{std::numeric_limits<std::size_t>::max()};  //!< caller's frame id
    mrpt::poses::CPose3D T_element_frame;  //!< pose of the frame in the element's frame
};

/** A frame pose in the world, for trajectory outputs. */
struct TimedPose
{
    double timestamp{0.0};                                             //!< the frame's time [s]
    std::size_t frame_index{std::numeric_limits<std::size_t>::max()};  //!< caller's frame id
    mrpt::poses::CPose3D T_world_frame;  //!< pose of the frame in the world
};

/** The trajectory of the rectifier (§2.2.3): actions a_0..a_{N-1} and, per
 * element, the observation simplified at l_d, kept in a CEntropyVoxelMap.
 * The pose of element i is a_0 ⊕ a_1 ⊕ ... ⊕ a_i (a_0: the first element in
 * the world, normally the identity since the world is the first camera
 * frame). With a 3DOF energy every action is kept planar ([δx, δz, δθ_y]).
 *
 * Changing actions moves only the elements whose poses change: a changed
 * a_k moves the segment k..N-1, never the elements before it.
 *
 * compress() is the trajectory compression of §2.2.4 (Eq. 13-14).
 * \ingroup emslam_rectify_grp */
class Trajectory
{
public:
    /** A new value for one action. */
    struct ActionChange
    {
        std::size_t index{0};         //!< the element whose action changes
        mrpt::poses::CPose3D action;  //!< its new value
    };

    /** An empty trajectory whose map has these options (validated). */
    explicit Trajectory(
        const emslam::CEntropyVoxelMap::TCreationOptions& map_options = {},
        const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options = {});

    /** 3 or 6, from the map's energy. */
    int dof() const { return m_map.creationOptions().dof; }
    /** True if the energy depends on the global alignment of the map (a
     * Manhattan-world or flat-floor term: Exp. 9, 10, 12), so a_0 matters. */
    bool dependsOnGlobalAlignment() const;

    /** Number of elements N. */
    std::size_t size() const { return m_actions.size(); }
    /** No element. */
    bool empty() const { return m_actions.empty(); }

    /** Appends an element: `action` = pose of the new frame in the previous
     * element's last frame (for the first element: its pose in the world),
     * `cloud` in the new frame (simplified here at l_d). Projected to 3DOF if
     * dof() == 3. `covariance`: the egomotion's uncertainty of `action`
     * (for the prior with PriorCovariance::Egomotion; without it, the
     * prior's fixed deviations of one step). */
    void append(
        const mrpt::poses::CPose3D& action,
        const emslam::maps::WeightedPointCloud& cloud,
        double timestamp,
        std::size_t frame_index = std::numeric_limits<std::size_t>::max(),
        const std::optional<ActionCovariance>& covariance = std::nullopt);

    /** Action i: pose of element i in element i−1 (a_0: element 0 in the world). */
    const mrpt::poses::CPose3D& action(std::size_t i) const { return m_actions.at(i); }
    /** Every action, a_0 first. */
    const std::vector<mrpt::poses::CPose3D>& actions() const { return m_actions; }
    /** Pose of element i in the world. */
    const mrpt::poses::CPose3D& pose(std::size_t i) const { return m_map.observationPose(i); }

    /** Current energy (O(1)): the map's entropy plus the odometry prior's
     * cost (0 unless enabled). */
    double energy() const { return entropy() + m_prior_sum; }
    /** The map's entropy alone (the paper's energy), averaged over the grid
     * phases if setGridPhases() asked for more than one. */
    double entropy() const;
    /** The odometry prior's part of energy(). */
    double priorEnergy() const { return m_prior_sum; }
    /** The odometry prior's cost of other actions (one per element; made
     * planar for 3DOF), e.g. those of the ground truth: 0 when it is off. */
    double priorEnergyOf(const std::vector<mrpt::poses::CPose3D>& actions) const;
    /** Recomputes the map's histograms from scratch (drops rounding drift of
     * long runs of incremental updates); returns the energy. */
    double recomputeEnergy();

    /** Enables (weight > 0) or disables the odometry prior: the actions as
     * appended (composed by compress()) are its references. */
    void setOdometryPrior(const OdometryPrior& prior);

    /** Averages the entropy over `phases` copies of the map whose voxel grids
     * are shifted by k / phases of a cell along (1, 1, 1), k = 0..phases-1
     * (averaged shifted histograms): the entropy of a hard-binned map changes
     * with the grid's phase as much as with sub-cell pose errors, and the
     * average removes most of that. 1 (the default) is the paper's single
     * grid. Costs `phases` times the moves. Throws unless 1 <= phases <= 8. */
    void setGridPhases(int phases);
    /** The number of grid phases set (1: one grid). */
    int gridPhases() const { return static_cast<int>(m_phase_maps.size()) + 1; }
    /** Threads of one change's map updates, 1 or 2 (see
     * IncrementalEntropyGrid::setThreads(): the same results, sooner);
     * kept through compress() and setGridPhases(). Throws otherwise. */
    void setThreads(int threads);
    /** Threads of one change's map updates (setThreads()). */
    int threads() const { return m_map.threads(); }
    /** The world shift of grid phase k of `phases`: k / phases of a cell
     * along (1, 1, 1). */
    static mrpt::poses::CPose3D gridPhaseShift(int k, int phases, double cell_size);
    /** Bins the map on cells 2^level times l_d (0: l_d, the map as built):
     * a coarser grid sees misalignments of up to its cell, so a rectification
     * may start coarse and refine (coarse to fine). The observations stay
     * simplified at l_d. append() and compress() need level 0 (they return
     * to it). Throws unless 0 <= level <= 4. */
    void setResolutionLevel(int level);
    /** The level setResolutionLevel() set (0: l_d). */
    int resolutionLevel() const { return m_level; }
    /** The odometry prior in use (weight 0: off). */
    const OdometryPrior& odometryPrior() const { return m_prior; }
    /** The egomotion's estimate of action i (the prior's reference). */
    const mrpt::poses::CPose3D& referenceAction(std::size_t i) const { return m_reference.at(i); }
    /** The egomotion's covariance of action i (composed by compress()). */
    const ActionCovariance& referenceCovariance(std::size_t i) const
    {
        return m_reference_cov.at(i);
    }

    /** Sets some actions (3DOF-projected if needed), moves the affected
     * segment in the map and returns the new energy. One undo record. */
    double changeActions(const std::vector<ActionChange>& changes);
    /** Sets all actions (size must be N); one undo record. */
    double setActions(const std::vector<mrpt::poses::CPose3D>& actions);
    /** True if the last change can be undone. */
    bool canRevert() const { return m_undo_valid; }
    /** Undoes the last changeActions()/setActions(); returns the energy. */
    double revertLastChange();
    /** Keeps the last change (forgets its undo record). */
    void commitChange();

    /** The map of the simplified observations at the current poses. */
    const emslam::CEntropyVoxelMap& map() const { return m_map; }

    /** Original frames of element i. */
    const std::vector<ElementFrame>& framesOf(std::size_t i) const { return m_frames.at(i); }
    /** The farthest point any appended frame put in the map, from that
     * frame [m]: how far one view reaches (compression keeps it). */
    double viewRange() const { return m_view_range; }
    /** Number of original frames in all elements. */
    std::size_t frameCount() const;
    /** World pose of every original frame, in order. */
    std::vector<TimedPose> framePoses() const;

    /** Trajectory compression (§2.2.4): fuses elements 2i and 2i+1 (Eq. 13:
     * the second cloud brought to the first's frame by a_{2i+1}, then the
     * union simplified again at l_d) and composes the actions (Eq. 14:
     * a'_0 = a_0, a'_i = a_{2i-1} ⊕ a_{2i}); an odd last element stays
     * alone. Poses of the kept elements do not change. N becomes ⌈N/2⌉. */
    void compress();
    /** True when compress() is due: N > `n_max` > 0 (N_max, §2.2.4; `n_max`
     * ≤ 0: never). */
    bool needsCompression(int n_max) const;
    /** Number of compress() calls so far. */
    std::size_t compressionCount() const { return m_compressions; }

private:
    /** Re-poses elements from `first` on from the actions. */
    double movePosesFrom(std::size_t first);
    /** Prior cost of action i (0 for a_0 or when the prior is off). */
    double priorTerm(std::size_t i) const;
    /** Prior cost of `action` in place of action i. */
    double priorTerm(std::size_t i, const mrpt::poses::CPose3D& action) const;
    /** Recomputes every prior term and their sum. */
    void recomputePrior();
    /** Updates the terms of these actions and the sum. */
    void updatePrior(const std::vector<ActionChange>& changed);
    /** Rebuilds the shifted copies from m_map (after compression). */
    void rebuildPhaseMaps();
    /** The mean of the phase-0 entropy `e0` and the copies' entropies. */
    double phaseMean(double e0) const;

    /** A copy of the map on a shifted grid: its observations sit at shift ⊕ pose. */
    struct PhaseMap
    {
        mrpt::poses::CPose3D shift;
        emslam::CEntropyVoxelMap map;
    };

    emslam::CEntropyVoxelMap m_map;
    std::vector<PhaseMap> m_phase_maps;  //!< grid phases 1..K-1 (empty: the paper's energy)
    std::vector<mrpt::poses::CPose3D> m_actions;
    std::vector<std::vector<ElementFrame>> m_frames;
    double m_view_range{0.0};  //!< viewRange()
    OdometryPrior m_prior;
    std::vector<mrpt::poses::CPose3D> m_reference;   //!< egomotion actions (prior references)
    std::vector<ActionCovariance> m_reference_cov;   //!< their covariances
    std::vector<ActionCovariance> m_reference_info;  //!< their information, for dof()
    std::vector<double> m_prior_terms;               //!< prior cost of each action
    double m_prior_sum{0.0};
    std::vector<emslam::CEntropyVoxelMap::ObservationMove> m_moves;          //!< scratch
    std::vector<emslam::CEntropyVoxelMap::ObservationMove> m_shifted_moves;  //!< scratch
    std::vector<ActionChange> m_undo;  //!< old values of the last change's actions
    bool m_undo_valid{false};
    std::size_t m_compressions{0};
    double m_base_cell_size{0.0};  //!< l_d: the cell size at resolution level 0
    int m_level{0};
};

}  // namespace emslam::rectify
