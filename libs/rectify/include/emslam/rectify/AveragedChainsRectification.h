// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/RectificationRunner.h>
#include <emslam/rectify/SerialRectification.h>

#include <functional>
#include <memory>
#include <vector>

namespace emslam::rectify
{
/** `chains = K` (> 1), serial mode: K independent serial rectifications of
 * the same frames, the k-th seeded with `seed + k`, whose trajectories are
 * averaged pose by pose (meanPose()). Beside the paper: each chain is the
 * paper's Metropolis-Hastings search, but on a voxel-grid entropy that is
 * rough below a cell, where a single chain ends depends on its seed (the
 * hall's loop gap moves by up to 0.5 m from seed to seed,
 * doc/notes/2026-12-03-averaged-chains-and-noise-weights.md); the mean of K chains keeps what they
 * agree on and divides the seed's share of the error by about √K.
 *
 * The chains run one after the other in the caller's thread (with
 * `threads = 2`, the odd ones in a second thread), so a rectification costs
 * K (K/2) times one chain's. framePoses() is every frame's
 * pose averaged over the chains. finish() also moves the first chain's
 * elements to their mean poses (its actions set from them), and
 * trajectory() returns that chain: its energy and entropy map are the
 * averaged trajectory's, up to the frames inside a compressed element, which
 * keep that chain's relative poses (each chain fused its own). statistics()
 * has one record per rectification: the attempts, successes and failures
 * summed over the chains, `seconds` the wall time of the call that ran them
 * all, the energies and the trace the first chain's. \ingroup emslam_rectify_grp
 * \sa SerialRectification, meanPose */
class AveragedChainsRectification : public RectificationRunner
{
public:
    /** `options.chains` chains over empty trajectories whose maps have `map_options` and
     * `insertion_options`. */
    AveragedChainsRectification(
        const TRectifierOptions& options,
        const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
        const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options = {});

    bool mapStable() const override;
    Progress progress() const override;
    std::vector<RectificationStats> statistics() const override;
    std::vector<TimedPose> framePoses() const override;
    const Trajectory& trajectory() const override;

    /** Number of chains (K). */
    std::size_t chainCount() const { return m_chains.size(); }
    /** Chain k's own trajectory (before finish(), or k > 0: not averaged). */
    const Trajectory& chainTrajectory(std::size_t k) const { return m_chains.at(k)->trajectory(); }

protected:
    void internalAddFrame(
        const mrpt::poses::CPose3D& action,
        const emslam::maps::WeightedPointCloud& cloud,
        double timestamp,
        std::size_t frame_index,
        const std::optional<ActionCovariance>& covariance) override;
    void internalFinish() override;

private:
    /** Calls `fn` on every chain (odd ones in a second thread if m_stride is 2). */
    void forEachChain(const std::function<void(SerialRectification&)>& fn);
    /** forEachChain(), timed: a call in which the chains rectified records
     * its wall time for that rectification's statistics. */
    void timedForEachChain(const std::function<void(SerialRectification&)>& fn);
    /** Sets the first chain's actions so that its element poses are the
     * chains' mean element poses. */
    void averageIntoFirstChain();
    /** Every frame's pose averaged over the chains. */
    std::vector<TimedPose> meanFramePoses() const;

    std::vector<std::unique_ptr<SerialRectification>> m_chains;
    std::size_t m_stride{1};               //!< 2: odd chains in a second thread
    std::vector<double> m_wall_seconds;    //!< per rectification, all chains [s]
    std::vector<TimedPose> m_mean_frames;  //!< framePoses() after finish()
};

}  // namespace emslam::rectify
