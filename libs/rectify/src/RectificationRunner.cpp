// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/AnyTimeRectification.h>
#include <emslam/rectify/AveragedChainsRectification.h>
#include <emslam/rectify/RectificationRunner.h>
#include <emslam/rectify/SerialRectification.h>

#include <stdexcept>

namespace emslam::rectify
{
void RectificationRunner::addFrame(
    const mrpt::poses::CPose3D& action,
    const emslam::maps::WeightedPointCloud& cloud,
    double timestamp,
    std::size_t frame_index,
    const std::optional<ActionCovariance>& covariance)
{
    if (m_finished)
    {
        throw std::logic_error("RectificationRunner::addFrame after finish()");
    }
    internalAddFrame(action, cloud, timestamp, frame_index, covariance);
}

void RectificationRunner::finish()
{
    if (m_finished)
    {
        return;
    }
    internalFinish();
    m_finished = true;
}

std::unique_ptr<RectificationRunner> createRectificationRunner(
    const TRectifierOptions& options,
    const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
    const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options)
{
    if (options.mode == RectificationMode::AnyTime)
    {
        return std::make_unique<AnyTimeRectification>(options, map_options, insertion_options);
    }
    if (options.chains > 1)
    {
        return std::make_unique<AveragedChainsRectification>(
            options, map_options, insertion_options);
    }
    return std::make_unique<SerialRectification>(options, map_options, insertion_options);
}

}  // namespace emslam::rectify
