// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/SerialRectification.h>
#include <emslam/rectify/VerticalBand.h>

#include <stdexcept>

namespace emslam::rectify
{
SerialRectification::SerialRectification(
    const TRectifierOptions& options,
    const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
    const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options)
    : m_options(options), m_trajectory(map_options, insertion_options), m_rectifier(options)
{
    m_trajectory.setOdometryPrior(options.odometryPrior());
    m_trajectory.setGridPhases(options.experimental_grid_phases);
    m_trajectory.setThreads(options.threads);
}

void SerialRectification::addFrame(
    const mrpt::poses::CPose3D& action,
    const emslam::maps::WeightedPointCloud& cloud,
    double timestamp,
    std::size_t frame_index,
    const std::optional<ActionCovariance>& covariance)
{
    if (m_finished)
    {
        throw std::logic_error("SerialRectification::addFrame after finish()");
    }
    m_trajectory.append(
        action,
        m_options.vertical_band
            ? keepVerticalBand(cloud, m_options.band_min_y, m_options.band_max_y)
            : cloud,
        timestamp, frame_index, covariance);
    if (m_options.n_max > 0 && m_trajectory.size() > static_cast<std::size_t>(m_options.n_max))
    {
        m_trajectory.compress();
    }
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

void SerialRectification::finish()
{
    if (m_finished)
    {
        return;
    }
    if (m_since_rectification > 0 && m_options.rectify_every > 0)
    {
        rectifyNow();
    }
    m_finished = true;
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
