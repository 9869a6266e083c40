// SPDX-License-Identifier: BSD-3-Clause
// Per-frame cost of the synthetic stereo renderer (emslam::sim), single-threaded:
// one stereo pair (left + right, noise, 8-bit conversion, the observation) per
// iteration, on the shipped worlds at their 320x240 default. Run:
// bench_sim [--benchmark_filter=...]. The counter "fps" is stereo frames per second.
#include "BenchCommon.h"

#include <emslam/sim/StereoSimulator.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <benchmark/benchmark.h>

#include <fstream>
#include <sstream>
#include <string>

namespace
{
std::string worldFile(const std::string& name)
{
    // benchmarks/ sits next to config/ in the source tree.
    return std::string(__FILE__).substr(0, std::string(__FILE__).rfind("/benchmarks/")) +
           "/config/sim/" + name + ".ini";
}

void renderWorld(benchmark::State& state, const std::string& name, int supersampling)
{
    std::ifstream in(worldFile(name));
    std::stringstream text;
    text << in.rdbuf();
    mrpt::config::CConfigFileMemory cfg(text.str());
    cfg.write("Camera", "supersampling", supersampling);
    mrpt::config::CConfigFileMemory reparsed(cfg.getContent());
    emslam::sim::StereoSimulator sim;
    sim.load(reparsed);
    std::size_t i = 0;
    for (auto _ : state)
    {
        auto f = sim.renderFrame(i);
        benchmark::DoNotOptimize(f.obs);
        i = (i + 17) % sim.frameCount();
    }
    state.counters["fps"] =
        benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_HallDoubleLoop(benchmark::State& s)
{
    renderWorld(s, "hall_double_loop", 1);
}
void BM_HallDoubleLoop_SS2(benchmark::State& s)
{
    renderWorld(s, "hall_double_loop", 2);
}
void BM_ThreeCorridors(benchmark::State& s)
{
    renderWorld(s, "three_corridors", 1);
}
void BM_TwoFloors(benchmark::State& s)
{
    renderWorld(s, "two_floors", 1);
}
void BM_RepetitiveCorridor(benchmark::State& s)
{
    renderWorld(s, "repetitive_corridor", 1);
}
void BM_MovingObject(benchmark::State& s)
{
    renderWorld(s, "moving_object", 1);
}
void BM_OutdoorGround(benchmark::State& s)
{
    renderWorld(s, "outdoor_ground", 1);
}
void BM_RiverBed(benchmark::State& s)
{
    renderWorld(s, "river_bed", 1);
}
}  // namespace

BENCHMARK(BM_HallDoubleLoop)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HallDoubleLoop_SS2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ThreeCorridors)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TwoFloors)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RepetitiveCorridor)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MovingObject)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OutdoorGround)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RiverBed)->Unit(benchmark::kMillisecond);

EMSLAM_BENCHMARK_MAIN();
