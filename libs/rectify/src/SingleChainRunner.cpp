// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/SingleChainRunner.h>
#include <emslam/rectify/VerticalBand.h>

namespace emslam::rectify
{
SingleChainRunner::SingleChainRunner(
    const TRectifierOptions& options,
    const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
    const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options)
    : m_options(options), m_trajectory(map_options, insertion_options), m_rectifier(options)
{
    m_trajectory.setOdometryPrior(options.odometryPrior());
    m_trajectory.setGridPhases(options.experimental_grid_phases);
    m_trajectory.setThreads(options.threads);
}

emslam::maps::WeightedPointCloud SingleChainRunner::keptPart(
    const emslam::maps::WeightedPointCloud& cloud) const
{
    return m_options.vertical_band
               ? keepVerticalBand(cloud, m_options.band_min_y, m_options.band_max_y)
               : cloud;
}

void SingleChainRunner::appendFrame(
    const mrpt::poses::CPose3D& action,
    const emslam::maps::WeightedPointCloud& cloud,
    double timestamp,
    std::size_t frame_index,
    const std::optional<ActionCovariance>& covariance)
{
    m_trajectory.append(action, cloud, timestamp, frame_index, covariance);
    if (m_trajectory.needsCompression(m_options.n_max))
    {
        m_trajectory.compress();
    }
}

}  // namespace emslam::rectify
