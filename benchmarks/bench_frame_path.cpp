// SPDX-License-Identifier: BSD-3-Clause
// The whole per-frame path of emslam-mapper on the KITTI 06 excerpt (51
// frames), one core: the stereo front-end and the egomotion as the mapper
// wires them (config/mapper/kitti.ini: sparse stereo at the features, guided
// matching), at full resolution (1226x370), at half (613x185) and at 320x240
// (how the cost grows with the pixels and the features); and Mapper itself
// (front-end, egomotion, dense cloud of the accepted frames, map insertion,
// serial rectification). Times are per frame (items). Run: bench_frame_path
// Needs the KITTI excerpt (EMSLAM_TEST_DATA, default ../shared/data).
#include "BenchCommon.h"

#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/slam/EntropySlam.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/config/CConfigFile.h>

#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <vector>

namespace
{
constexpr int EXCERPT_FRAMES = 51;

using Observations = std::vector<mrpt::obs::CObservationStereoImages::Ptr>;

/** The excerpt's observations at one size, read once; empty if absent. */
const Observations& excerpt(int width, int height)
{
    static std::map<int, Observations> cache;
    auto& obs = cache[width];
    if (obs.empty())
    {
        for (int i = 0; i < EXCERPT_FRAMES; ++i)
        {
            auto o = emslam::bench::kittiObservation(i, width, height);
            if (!o)
            {
                obs.clear();
                break;
            }
            o->timestamp = mrpt::Clock::fromDouble(0.1 * i);
            obs.push_back(o);
        }
    }
    return obs;
}

emslam::slam::EntropySlam::TParameters kittiParameters(int width)
{
    mrpt::config::CConfigFile cfg(emslam::bench::sourceDir() + "/config/mapper/kitti.ini");
    emslam::slam::EntropySlam::TParameters p;
    p.loadFromConfigFile(cfg);
    if (width > 0)
    {
        // The paper's size, as bench_egomotion and bench_stereo_frontend run it.
        p.stereo.image_scale = 1.0;
        p.stereo.num_disparities = 64;
    }
    return p;
}

void runFrontEndEgomotion(benchmark::State& state, int width, int height)
{
    const Observations& obs = excerpt(width, height);
    if (obs.empty())
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    const auto p = kittiParameters(width);
    std::size_t failures = 0, points = 0;
    for (auto _ : state)
    {
        // Wired as Mapper wires them.
        emslam::stereo::StereoFrontEnd front(p.stereo);
        emslam::egomotion::EgomotionEstimator egomotion(p.egomotion);
        front.setPixelSelector([&egomotion](const cv::Mat& image)
                               { return egomotion.locateFeatures(image); });
        failures = points = 0;
        for (const auto& o : obs)
        {
            const auto f = front.process(*o);
            points += f.size();
            const auto r = egomotion.process(f);
            failures += &o != &obs.front() && !r.ok;
        }
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * EXCERPT_FRAMES);
    state.counters["ms_per_frame"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * EXCERPT_FRAMES / 1000.0,
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["failed_steps"] = static_cast<double>(failures);
    state.counters["points_per_frame"] = static_cast<double>(points) / EXCERPT_FRAMES;
}

void runMapper(benchmark::State& state)
{
    const Observations& obs = excerpt(0, 0);
    if (obs.empty())
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    const auto p = kittiParameters(0);
    for (auto _ : state)
    {
        emslam::slam::EntropySlam mapper(p);
        for (const auto& o : obs)
        {
            mapper.process(*o);
        }
        mapper.finish();
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * EXCERPT_FRAMES);
    state.counters["ms_per_frame"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * EXCERPT_FRAMES / 1000.0,
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
}  // namespace

BENCHMARK_CAPTURE(runFrontEndEgomotion, KittiFull, 0, 0)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);
BENCHMARK_CAPTURE(runFrontEndEgomotion, Kitti613x185, 613, 185)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);
BENCHMARK_CAPTURE(runFrontEndEgomotion, Kitti320x240, 320, 240)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);
BENCHMARK(runMapper)->Name("Mapper/KittiFull")->Unit(benchmark::kMillisecond)->MinTime(3.0);

EMSLAM_BENCHMARK_MAIN();
