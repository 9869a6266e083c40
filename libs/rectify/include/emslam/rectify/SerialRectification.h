// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/SingleChainRunner.h>

namespace emslam::rectify
{
/** Serial mode: rectify every S_rec accepted frames, in the caller's thread.
 * \ingroup emslam_rectify_grp \sa RectificationRunner, SingleChainRunner */
class SerialRectification : public SingleChainRunner
{
public:
    /** An empty trajectory whose map has `map_options` and `insertion_options`, rectified with
     * `options`. */
    SerialRectification(
        const TRectifierOptions& options,
        const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
        const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options = {});

    bool mapStable() const override;
    std::vector<RectificationStats> statistics() const override { return m_stats; }
    Progress progress() const override
    {
        return {m_stats.size(), m_stats.empty() ? 0.0 : m_stats.back().energy_after};
    }
    std::vector<TimedPose> framePoses() const override { return m_trajectory.framePoses(); }
    const Trajectory& trajectory() const override { return m_trajectory; }

    /** Sets every action (size N), e.g. to the mean of several runs, and
     * keeps the change (AveragedChainsRectification). */
    void replaceActions(const std::vector<mrpt::poses::CPose3D>& actions);

protected:
    void internalAddFrame(
        const mrpt::poses::CPose3D& action,
        const emslam::maps::WeightedPointCloud& cloud,
        double timestamp,
        std::size_t frame_index,
        const std::optional<ActionCovariance>& covariance) override;
    void internalFinish() override;

private:
    void rectifyNow();

    std::vector<RectificationStats> m_stats;
    std::size_t m_since_rectification{0};
};

}  // namespace emslam::rectify
