// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/SerialRectification.h>

namespace emslam::rectify
{
SerialRectification::SerialRectification(
    const TRectifierOptions& options,
    const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
    const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options)
    : SingleChainRunner(options, map_options, insertion_options)
{
}

void SerialRectification::internalAddFrame(
    const mrpt::poses::CPose3D& action,
    const emslam::maps::WeightedPointCloud& cloud,
    double timestamp,
    std::size_t frame_index,
    const std::optional<ActionCovariance>& covariance)
{
    appendFrame(action, keptPart(cloud), timestamp, frame_index, covariance);
    ++m_since_rectification;
    if (m_options.rectify_every > 0 &&
        m_since_rectification >= static_cast<std::size_t>(m_options.rectify_every))
    {
        rectifyNow();
    }
}

void SerialRectification::rectifyNow()
{
    m_since_rectification = 0;
    if (m_trajectory.size() >= 2)
    {
        m_stats.push_back(m_rectifier.rectify(m_trajectory));
    }
}

void SerialRectification::internalFinish()
{
    if (m_since_rectification > 0 && m_options.rectify_every > 0)
    {
        rectifyNow();
    }
}

void SerialRectification::replaceActions(const std::vector<mrpt::poses::CPose3D>& actions)
{
    m_trajectory.setActions(actions);
    m_trajectory.commitChange();
}

bool SerialRectification::mapStable() const
{
    return m_since_rectification == 0 && !m_stats.empty() && m_stats.back().converged;
}

}  // namespace emslam::rectify
