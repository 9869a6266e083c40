// SPDX-License-Identifier: BSD-3-Clause
// Time of associateByTimestamp() (emslam-eval's and the mapper's --gt pairing)
// on adversarial inputs where every pose has thousands of candidates within
// max_dt: the all-pairs greedy of TUM's associate.py is O(N^2) there. Google
// Benchmark fits the complexity over N = 1k..64k (expect ~N log N). Run:
// bench_association [--benchmark_filter=...].
#include "BenchCommon.h"

#include <emslam/eval/TrajectoryMetrics.h>

#include <benchmark/benchmark.h>

#include <cstddef>
#include <functional>
#include <vector>

namespace
{
using emslam::io::TumTrajectory;

TumTrajectory trajectoryAt(const std::vector<double>& times)
{
    TumTrajectory t;
    for (std::size_t i = 0; i < times.size(); ++i)
    {
        t.add(times[i], mrpt::poses::CPose3D(static_cast<double>(i), 0, 0, 0, 0, 0));
    }
    return t;
}

/** Runs the association of `gt` and `est` stamps made by `make(n, is_gt)`. */
void associate(
    benchmark::State& state, const std::function<std::vector<double>(std::size_t, bool)>& make)
{
    const auto n = static_cast<std::size_t>(state.range(0));
    const TumTrajectory gt = trajectoryAt(make(n, true)), est = trajectoryAt(make(n, false));
    std::size_t pairs = 0;
    for (auto _ : state)
    {
        const auto a = emslam::eval::associateByTimestamp(gt, est, 0.02);
        pairs = a.size();
        benchmark::DoNotOptimize(pairs);
    }
    state.counters["pairs"] = static_cast<double>(pairs);
    state.SetComplexityN(state.range(0));
}

/** Every pose of both files at one stamp. */
void BM_AllStampsEqual(benchmark::State& state)
{
    associate(state, [](std::size_t n, bool) { return std::vector<double>(n, 1000.0); });
}

/** Every estimate at one stamp, the ground truth spread 1 us apart around it. */
void BM_OneStampAgainstADenseWindow(benchmark::State& state)
{
    associate(
        state,
        [](std::size_t n, bool is_gt)
        {
            std::vector<double> t(n, 1000.0);
            for (std::size_t i = 0; is_gt && i < n; ++i)
            {
                t[i] += (i % 2 == 1 ? 1e-6 : -1e-6) * static_cast<double>((i + 1) / 2);
            }
            return t;
        });
}

/** Distinct, interleaved stamps in both files, all within max_dt of each other. */
void BM_InterleavedDenseWindow(benchmark::State& state)
{
    associate(
        state,
        [](std::size_t n, bool is_gt)
        {
            std::vector<double> t(n);
            for (std::size_t i = 0; i < n; ++i)
            {
                t[i] = 1000.0 + 1e-7 * static_cast<double>(2 * i + (is_gt ? 1 : 0));
            }
            return t;
        });
}

/** Estimates in reverse time order of a dense window (worst order for a scan). */
void BM_ReversedDenseWindow(benchmark::State& state)
{
    associate(
        state,
        [](std::size_t n, bool is_gt)
        {
            std::vector<double> t(n);
            for (std::size_t i = 0; i < n; ++i)
            {
                const double k = static_cast<double>(is_gt ? i : n - 1 - i);
                t[i] = 1000.0 + 3e-7 * k + (is_gt ? 0.0 : 1e-7);
            }
            return t;
        });
}

/** A plain 10 Hz trajectory against 200 Hz ground truth: the common case. */
void BM_TenHertzAgainstTwoHundredHertz(benchmark::State& state)
{
    associate(
        state,
        [](std::size_t n, bool is_gt)
        {
            std::vector<double> t(n);
            for (std::size_t i = 0; i < n; ++i)
            {
                t[i] = 1000.0 + static_cast<double>(i) * (is_gt ? 0.005 : 0.1);
            }
            return t;
        });
}

}  // namespace

BENCHMARK(BM_AllStampsEqual)->RangeMultiplier(4)->Range(1 << 10, 1 << 16)->Complexity();
BENCHMARK(BM_OneStampAgainstADenseWindow)
    ->RangeMultiplier(4)
    ->Range(1 << 10, 1 << 16)
    ->Complexity();
BENCHMARK(BM_InterleavedDenseWindow)->RangeMultiplier(4)->Range(1 << 10, 1 << 16)->Complexity();
BENCHMARK(BM_ReversedDenseWindow)->RangeMultiplier(4)->Range(1 << 10, 1 << 16)->Complexity();
BENCHMARK(BM_TenHertzAgainstTwoHundredHertz)
    ->RangeMultiplier(4)
    ->Range(1 << 10, 1 << 16)
    ->Complexity();
EMSLAM_BENCHMARK_MAIN();
