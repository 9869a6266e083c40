// SPDX-License-Identifier: BSD-3-Clause
// Rectifier throughput: Metropolis-Hastings attempts per second on a
// trajectory of N = 60 elements x 2,000 weighted points at l_d = 0.15 m, one
// thread (the target: >= 500 attempts/s), and with the map's updates
// split over two threads (`[Rectifier] threads = 2`).
#include <emslam/rectify/TrajectoryRectifier.h>

#include <benchmark/benchmark.h>

#include <BenchCommon.h>

#include <random>

using emslam::maps::EnergyType;
using emslam::rectify::RectificationStats;
using emslam::rectify::Trajectory;
using emslam::rectify::TrajectoryRectifier;
using emslam::rectify::TRectifierOptions;
using mrpt::poses::CPose3D;

namespace
{
constexpr std::size_t NUM_ELEMENTS = 60;
constexpr std::size_t POINTS = 2000;

/** 2,000 simplified points (integer weights) of a 3 m x 2.4 m corridor seen
 * 0.5-6 m ahead: floor, ceiling and both walls, in the camera frame. */
emslam::maps::WeightedPointCloud corridorView(std::mt19937& rng)
{
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::uniform_int_distribution<int> w(1, 60);
    emslam::maps::WeightedPointCloud c;
    for (std::size_t j = 0; j < POINTS; ++j)
    {
        const float z = 0.5f + 5.5f * u(rng);
        const float across = u(rng);
        switch (j % 4)
        {
            case 0:
                c.push_back({-1.5f + 3.f * across, 1.2f, z}, float(w(rng)));
                break;
            case 1:
                c.push_back({-1.5f + 3.f * across, -1.2f, z}, float(w(rng)));
                break;
            case 2:
                c.push_back({-1.5f, -1.2f + 2.4f * across, z}, float(w(rng)));
                break;
            default:
                c.push_back({1.5f, -1.2f + 2.4f * across, z}, float(w(rng)));
                break;
        }
    }
    return c;
}

Trajectory makeTrajectory(EnergyType energy)
{
    emslam::CEntropyVoxelMap::TCreationOptions o;
    o.cell_size = 0.15;
    o.energy = energy;
    o.dof = emslam::maps::energyDof(energy);
    Trajectory t(o);
    std::mt19937 rng(2024);
    for (std::size_t i = 0; i < NUM_ELEMENTS; ++i)
    {
        // 0.4 m forward per element, with a small heading error.
        t.append(
            i == 0 ? CPose3D() : CPose3D(0.0, 0.0, 0.4, 0.0, 0.002, 0.0), corridorView(rng),
            static_cast<double>(i), i);
    }
    return t;
}

/** The paper's search (S_sel, ε, the entropy alone, box proposals): the
 * numbers stay comparable with the earlier runs of this benchmark. */
TRectifierOptions paperOptions()
{
    TRectifierOptions o;
    o.prior_weight = 0;
    o.prior_covariance = emslam::rectify::PriorCovariance::Fixed;
    o.proposal = emslam::rectify::ProposalShape::Box;
    return o;
}

/** Arguments: the energy, and the threads of the map's updates (2:
 * `[Rectifier] threads = 2`, the same attempts side by side; real time). */
void BM_RectifierAttempt(benchmark::State& state)
{
    const auto energy = static_cast<EnergyType>(state.range(0));
    Trajectory t = makeTrajectory(energy);
    t.setThreads(static_cast<int>(state.range(1)));
    const TRectifierOptions opt = paperOptions();
    TrajectoryRectifier r(opt);
    RectificationStats s;
    r.begin(t, s);
    for (auto _ : state)
    {
        benchmark::DoNotOptimize(r.attempt(t, s));
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
    state.SetLabel(emslam::maps::toString(energy));
}

void BM_RectifyToConvergence(benchmark::State& state)
{
    const auto energy = static_cast<EnergyType>(state.range(0));
    for (auto _ : state)
    {
        state.PauseTiming();
        Trajectory t = makeTrajectory(energy);
        TrajectoryRectifier r{paperOptions()};
        state.ResumeTiming();
        const RectificationStats s = r.rectify(t);
        state.counters["attempts"] = static_cast<double>(s.attempts);
    }
    state.SetLabel(emslam::maps::toString(energy));
}
}  // namespace

BENCHMARK(BM_RectifierAttempt)
    ->Args({static_cast<int>(EnergyType::PlanarLowStructured), 1})
    ->Args({static_cast<int>(EnergyType::PlanarStructured), 1})
    ->Args({static_cast<int>(EnergyType::Unstructured), 1})
    ->Args({static_cast<int>(EnergyType::LowStructured), 1})
    ->Args({static_cast<int>(EnergyType::Structured), 1})
    ->Args({static_cast<int>(EnergyType::Unstructured), 2})
    ->Args({static_cast<int>(EnergyType::LowStructured), 2})
    ->Args({static_cast<int>(EnergyType::Structured), 2})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_RectifyToConvergence)
    ->Arg(static_cast<int>(EnergyType::PlanarLowStructured))
    ->Arg(static_cast<int>(EnergyType::Structured))
    ->Unit(benchmark::kMillisecond);

EMSLAM_BENCHMARK_MAIN();
