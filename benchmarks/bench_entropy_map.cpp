// SPDX-License-Identifier: BSD-3-Clause
// Entropy map costs for the rectifier: full energy evaluation and incremental
// moves, 60 observations x 2,000 weighted points at l_d = 0.15 m, one thread.
#include <emslam/maps/CEntropyVoxelMap.h>

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

using emslam::CEntropyVoxelMap;
using emslam::maps::EnergyType;
using mrpt::poses::CPose3D;

namespace
{
constexpr std::size_t NUM_OBS = 60;
constexpr std::size_t POINTS_PER_OBS = 2000;
constexpr double CELL = 0.15;
constexpr double DEG = M_PI / 180.0;

/** A camera moving 0.4 m per frame along a 3 m x 2.4 m corridor (z forward,
 * y down); each observation holds 2,000 simplified points of the floor,
 * ceiling and walls 0.5-6 m ahead, with integer weights 1-60, in its own
 * frame. Poses get a small deterministic error, as egomotion would give. */
CEntropyVoxelMap makeMap(EnergyType energy)
{
    CEntropyVoxelMap::TCreationOptions o;
    o.cell_size = CELL;
    o.energy = energy;
    o.dof = emslam::maps::energyDof(energy);
    CEntropyVoxelMap m(o);
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::uniform_int_distribution<int> w(1, 60);
    for (std::size_t i = 0; i < NUM_OBS; i++)
    {
        emslam::maps::WeightedPointCloud c;
        for (std::size_t j = 0; j < POINTS_PER_OBS; j++)
        {
            const double z = 0.5 + 5.5 * u(rng);
            double x = 0, y = 0;
            switch (j % 4)
            {
                case 0:  // floor
                    x = -1.5 + 3.0 * u(rng);
                    y = 1.2;
                    break;
                case 1:  // ceiling
                    x = -1.5 + 3.0 * u(rng);
                    y = -1.2;
                    break;
                case 2:  // left wall
                    x = -1.5;
                    y = -1.2 + 2.4 * u(rng);
                    break;
                default:  // right wall
                    x = 1.5;
                    y = -1.2 + 2.4 * u(rng);
                    break;
            }
            c.push_back(
                mrpt::math::TPoint3Df(
                    static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)),
                static_cast<float>(w(rng)));
        }
        const CPose3D noise(
            0.02 * (u(rng) - 0.5), 0.02 * (u(rng) - 0.5), 0.02 * (u(rng) - 0.5),
            DEG * (u(rng) - 0.5), DEG * (u(rng) - 0.5), DEG * (u(rng) - 0.5));
        m.insertWeightedCloud(
            c, CPose3D(0, 0, 0.4 * static_cast<double>(i), 0, 0, 0) + noise, true);
    }
    return m;
}

/** Random perturbations of the paper's scale (ε = 5 cm, 3°). */
std::vector<CPose3D> perturbations(double eps_xyz, double eps_rot)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<CPose3D> out;
    for (int k = 0; k < 1024; k++)
    {
        out.emplace_back(
            eps_xyz * u(rng), eps_xyz * u(rng), eps_xyz * u(rng), eps_rot * u(rng),
            eps_rot * u(rng), eps_rot * u(rng));
    }
    return out;
}

void reportMemory(benchmark::State& state, const CEntropyVoxelMap& m)
{
    const auto mem = m.memoryStats();
    state.counters["occupied_3d_cells"] = static_cast<double>(mem.occupied_cells_3d);
    state.counters["hist_bytes_per_occupied_cell"] = mem.bytes_per_occupied_cell;
    if (const auto* h3 = m.trackedHistogram(emslam::maps::EntropyTerm::H3D))
    {
        state.counters["bytes_per_3d_cell"] =
            static_cast<double>(h3->memoryBytes()) / static_cast<double>(h3->occupiedCells());
    }
    state.counters["hist_MB"] = static_cast<double>(mem.histogram_bytes) / 1e6;
    state.counters["obs_MB"] = static_cast<double>(mem.observation_bytes) / 1e6;
}

/** Rebuilds every tracked histogram from the 60 observations and evaluates
 * the energy (what a from-scratch evaluation of a trajectory costs). */
void BM_FullEnergyEvaluation(benchmark::State& state)
{
    auto m = makeMap(static_cast<EnergyType>(state.range(0)));
    for (auto _ : state)
    {
        benchmark::DoNotOptimize(m.recomputeFromScratch());
    }
    state.SetLabel(emslam::maps::toString(m.creationOptions().energy));
    reportMemory(state, m);
}

/** Energy from the running sums (what the rectifier reads after each move). */
void BM_EnergyFromRunningSums(benchmark::State& state)
{
    auto m = makeMap(EnergyType::Structured);
    for (auto _ : state)
    {
        benchmark::DoNotOptimize(m.energy());
    }
}

/** moveObservation() of one observation (2,000 points) to its pose ⊕ a random
 * ε perturbation; range(1) = perturbation scale in cm (rotation 3° per 5 cm). */
void BM_MoveObservation(benchmark::State& state)
{
    auto m = makeMap(static_cast<EnergyType>(state.range(0)));
    const double eps = static_cast<double>(state.range(1)) / 100.0;
    const auto d = perturbations(eps, 3 * DEG * eps / 0.05);
    std::vector<CPose3D> base;
    for (std::size_t i = 0; i < m.observationCount(); i++)
    {
        base.push_back(m.observationPose(i));
    }
    std::size_t k = 0;
    for (auto _ : state)
    {
        const std::size_t i = (k * 7) % NUM_OBS;
        benchmark::DoNotOptimize(m.moveObservation(i, base[i] + d[k % d.size()]));
        k++;
    }
    state.SetLabel(
        emslam::maps::toString(m.creationOptions().energy) + ", eps " +
        std::to_string(state.range(1)) + " cm");
}

/** A rejected Metropolis attempt: move one observation, then revert. */
void BM_MoveAndRevert(benchmark::State& state)
{
    auto m = makeMap(EnergyType::Structured);
    const auto d = perturbations(0.05, 3 * DEG);
    std::size_t k = 0;
    for (auto _ : state)
    {
        const std::size_t i = (k * 7) % NUM_OBS;
        m.moveObservation(i, m.observationPose(i) + d[k % d.size()]);
        benchmark::DoNotOptimize(m.revertLastMove());
        k++;
    }
}

/** A batch move of 6 observations (S_sel = 10% of 60), as the rectifier does. */
void BM_MoveSixObservations(benchmark::State& state)
{
    auto m = makeMap(EnergyType::Structured);
    const auto d = perturbations(0.05, 3 * DEG);
    std::vector<CPose3D> base;
    for (std::size_t i = 0; i < m.observationCount(); i++)
    {
        base.push_back(m.observationPose(i));
    }
    std::vector<CEntropyVoxelMap::ObservationMove> moves(6);
    std::size_t k = 0;
    for (auto _ : state)
    {
        for (std::size_t j = 0; j < moves.size(); j++)
        {
            const std::size_t i = (k * 7 + j * 11) % NUM_OBS;
            moves[j].index = i;
            moves[j].pose = base[i] + d[(k + j) % d.size()];
        }
        benchmark::DoNotOptimize(m.moveObservations(moves));
        k++;
    }
}
}  // namespace

constexpr auto U = static_cast<int>(EnergyType::Unstructured);
constexpr auto S = static_cast<int>(EnergyType::Structured);
constexpr auto PS = static_cast<int>(EnergyType::PlanarStructured);

BENCHMARK(BM_FullEnergyEvaluation)->Arg(U)->Arg(S)->Arg(PS)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EnergyFromRunningSums)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_MoveObservation)
    ->Args({U, 5})
    ->Args({S, 5})
    ->Args({PS, 5})
    ->Args({S, 100})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MoveAndRevert)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MoveSixObservations)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
