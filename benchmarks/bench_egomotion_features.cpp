// SPDX-License-Identifier: BSD-3-Clause
// Per-frame cost of the appearance stages of egomotion (§2.1.1-2.1.2): GLM
// extraction, log-polar descriptors and mutual matching, single-threaded, on
// KITTI 06 frames 0 and 1 at 320x240 (the paper's size) and at full size.
// Run: bench_egomotion_features [--benchmark_filter=...]
// Needs the KITTI excerpt (EMSLAM_TEST_DATA, default ../shared/data).
#include "BenchCommon.h"

#include <emslam/egomotion/FeatureMatcher.h>
#include <emslam/egomotion/GlmFeatureExtractor.h>
#include <emslam/egomotion/LogPolarDescriptor.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <utility>

namespace
{
using emslam::egomotion::Descriptors;
using emslam::egomotion::FeatureList;
using emslam::egomotion::GlmFeatureExtractor;
using emslam::egomotion::LogPolarDescriptorExtractor;
using emslam::stereo::StereoFrame;

/** KITTI 06 frame `index` through the stereo front-end, optionally cropped to
 * 4:3 and resized (width > 0). Empty frame if the data is absent. */
StereoFrame kittiFrame(int index, int width, int height)
{
    const auto obs = emslam::bench::kittiObservation(index, width, height);
    if (!obs)
    {
        return {};
    }
    emslam::stereo::StereoMatcher::TParameters p;
    p.num_disparities = width > 0 ? 64 : 128;
    p.max_range = 80.0;
    return emslam::stereo::StereoFrontEnd(p).process(*obs);
}

/** Frames 0 and 1 with their features and descriptors, built once per size. */
struct FramePair
{
    StereoFrame frame[2];
    FeatureList features[2];
    Descriptors descriptors[2];
};

const FramePair& framePair(int width, int height)
{
    static std::map<std::pair<int, int>, FramePair> cache;
    auto it = cache.find({width, height});
    if (it == cache.end())
    {
        FramePair fp;
        for (int i = 0; i < 2; ++i)
        {
            fp.frame[i] = kittiFrame(i, width, height);
            if (fp.frame[i].empty())
            {
                continue;
            }
            fp.features[i] = GlmFeatureExtractor().extract(fp.frame[i]);
            fp.descriptors[i] =
                LogPolarDescriptorExtractor().compute(fp.frame[i].intensity, fp.features[i]);
        }
        it = cache.emplace(std::make_pair(width, height), std::move(fp)).first;
    }
    return it->second;
}

void runGlm(benchmark::State& state, int width, int height)
{
    const auto& fp = framePair(width, height);
    if (fp.frame[0].empty())
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    const GlmFeatureExtractor ex;
    std::size_t n = 0;
    for (auto _ : state)
    {
        n = ex.extract(fp.frame[0]).size();
        benchmark::DoNotOptimize(n);
    }
    state.counters["points"] = static_cast<double>(fp.frame[0].size());
    state.counters["features"] = static_cast<double>(n);
}

void runDescriptors(benchmark::State& state, int width, int height)
{
    const auto& fp = framePair(width, height);
    if (fp.frame[0].empty())
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    const LogPolarDescriptorExtractor ex;
    for (auto _ : state)
    {
        auto d = ex.compute(fp.frame[0].intensity, fp.features[0]);
        benchmark::DoNotOptimize(d.data.data());
    }
    state.counters["features"] = static_cast<double>(fp.features[0].size());
}

void runMatching(benchmark::State& state, int width, int height)
{
    const auto& fp = framePair(width, height);
    if (fp.frame[0].empty() || fp.frame[1].empty())
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    std::size_t n = 0;
    for (auto _ : state)
    {
        n = emslam::egomotion::matchMutual(fp.descriptors[0], fp.descriptors[1], 0.8f).size();
        benchmark::DoNotOptimize(n);
    }
    state.counters["features0"] = static_cast<double>(fp.features[0].size());
    state.counters["features1"] = static_cast<double>(fp.features[1].size());
    state.counters["matches"] = static_cast<double>(n);
}

void BM_Kitti320x240_Glm(benchmark::State& s)
{
    runGlm(s, 320, 240);
}
void BM_Kitti320x240_LogPolar(benchmark::State& s)
{
    runDescriptors(s, 320, 240);
}
void BM_Kitti320x240_MatchMutual(benchmark::State& s)
{
    runMatching(s, 320, 240);
}
void BM_KittiFull_Glm(benchmark::State& s)
{
    runGlm(s, 0, 0);
}
void BM_KittiFull_LogPolar(benchmark::State& s)
{
    runDescriptors(s, 0, 0);
}
void BM_KittiFull_MatchMutual(benchmark::State& s)
{
    runMatching(s, 0, 0);
}
}  // namespace

BENCHMARK(BM_Kitti320x240_Glm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kitti320x240_LogPolar)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kitti320x240_MatchMutual)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_Glm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_LogPolar)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_MatchMutual)->Unit(benchmark::kMillisecond);

EMSLAM_BENCHMARK_MAIN();
