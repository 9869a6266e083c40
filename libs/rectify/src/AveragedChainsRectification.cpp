// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/rectify/AveragedChainsRectification.h>
#include <emslam/rectify/PoseMean.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <future>
#include <stdexcept>

namespace emslam::rectify
{
AveragedChainsRectification::AveragedChainsRectification(
    const TRectifierOptions& options,
    const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
    const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options)
{
    if (options.chains < 2 || options.mode != RectificationMode::Serial)
    {
        throw std::invalid_argument(
            "AveragedChainsRectification: needs chains >= 2 and mode = serial");
    }
    m_stride = options.threads >= 2 ? 2 : 1;
    for (int k = 0; k < options.chains; ++k)
    {
        TRectifierOptions chain = options;
        chain.chains = 1;
        chain.seed = options.seed + static_cast<std::uint64_t>(k);
        m_chains.push_back(
            std::make_unique<SerialRectification>(chain, map_options, insertion_options));
    }
}

void AveragedChainsRectification::internalAddFrame(
    const mrpt::poses::CPose3D& action,
    const emslam::maps::WeightedPointCloud& cloud,
    double timestamp,
    std::size_t frame_index,
    const std::optional<ActionCovariance>& covariance)
{
    timedForEachChain([&](SerialRectification& c)
                      { c.addFrame(action, cloud, timestamp, frame_index, covariance); });
}

void AveragedChainsRectification::timedForEachChain(
    const std::function<void(SerialRectification&)>& fn)
{
    const std::size_t before = m_chains.front()->progress().rectifications;
    const auto t0 = std::chrono::steady_clock::now();
    forEachChain(fn);
    if (m_chains.front()->progress().rectifications > before)
    {
        m_wall_seconds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
}

void AveragedChainsRectification::forEachChain(const std::function<void(SerialRectification&)>& fn)
{
    // With two threads the odd chains run beside the even ones: the chains
    // share nothing but the (const) input, and each repeats exactly.
    const auto run = [&](std::size_t first)
    {
        for (std::size_t k = first; k < m_chains.size(); k += m_stride)
        {
            fn(*m_chains[k]);
        }
    };
    if (m_stride == 1)
    {
        run(0);
        return;
    }
    auto odd = std::async(std::launch::async, run, 1);
    run(0);
    odd.get();
}

void AveragedChainsRectification::internalFinish()
{
    timedForEachChain([](SerialRectification& c) { c.finish(); });
    m_mean_frames = meanFramePoses();
    averageIntoFirstChain();
}

void AveragedChainsRectification::averageIntoFirstChain()
{
    const std::size_t n = m_chains.front()->trajectory().size();
    if (n == 0)
    {
        return;
    }
    // Every chain saw the same frames and compressed at the same N, so
    // element i is the same frames in every chain.
    std::vector<mrpt::poses::CPose3D> mean(n);
    std::vector<mrpt::poses::CPose3D> poses(m_chains.size());
    for (std::size_t i = 0; i < n; ++i)
    {
        for (std::size_t k = 0; k < m_chains.size(); ++k)
        {
            poses[k] = m_chains[k]->trajectory().pose(i);
        }
        mean[i] = meanPose(poses);
    }
    m_chains.front()->replaceActions(actionsBetween(mean));
}

bool AveragedChainsRectification::mapStable() const
{
    return std::all_of(
        m_chains.begin(), m_chains.end(), [](const auto& c) { return c->mapStable(); });
}

RectificationRunner::Progress AveragedChainsRectification::progress() const
{
    return m_chains.front()->progress();
}

std::vector<RectificationStats> AveragedChainsRectification::statistics() const
{
    std::vector<RectificationStats> sum = m_chains.front()->statistics();
    for (std::size_t k = 1; k < m_chains.size(); ++k)
    {
        const auto other = m_chains[k]->statistics();
        for (std::size_t r = 0; r < std::min(sum.size(), other.size()); ++r)
        {
            sum[r].attempts += other[r].attempts;
            sum[r].successes += other[r].successes;
            sum[r].accepted_worse += other[r].accepted_worse;
            sum[r].failures += other[r].failures;
            sum[r].coarse_attempts += other[r].coarse_attempts;
            sum[r].unconfirmed += other[r].unconfirmed;
            sum[r].converged = sum[r].converged && other[r].converged;
        }
    }
    for (std::size_t r = 0; r < std::min(sum.size(), m_wall_seconds.size()); ++r)
    {
        sum[r].seconds = m_wall_seconds[r];
    }
    return sum;
}

std::vector<TimedPose> AveragedChainsRectification::framePoses() const
{
    return finished() ? m_mean_frames : meanFramePoses();
}

std::vector<TimedPose> AveragedChainsRectification::meanFramePoses() const
{
    std::vector<TimedPose> out = m_chains.front()->framePoses();
    std::vector<std::vector<TimedPose>> others;
    for (std::size_t k = 1; k < m_chains.size(); ++k)
    {
        others.push_back(m_chains[k]->framePoses());
    }
    std::vector<mrpt::poses::CPose3D> poses(m_chains.size());
    for (std::size_t f = 0; f < out.size(); ++f)
    {
        poses[0] = out[f].T_world_frame;
        for (std::size_t k = 1; k < m_chains.size(); ++k)
        {
            poses[k] = others[k - 1].at(f).T_world_frame;
        }
        out[f].T_world_frame = meanPose(poses);
    }
    return out;
}

const Trajectory& AveragedChainsRectification::trajectory() const
{
    return m_chains.front()->trajectory();
}

}  // namespace emslam::rectify
