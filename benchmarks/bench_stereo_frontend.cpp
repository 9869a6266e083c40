// SPDX-License-Identifier: BSD-3-Clause
// Per-frame cost of the stereo front-end (rectification + disparity + 3D) on
// real images, single-threaded. Run: bench_stereo_frontend [--benchmark_filter=...]
// Needs the KITTI / EuRoC excerpts (EMSLAM_TEST_DATA, default ../shared/data).
#include "BenchCommon.h"

#include <emslam/io/CalibrationFiles.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/system/filesystem.h>

#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>
#include <string>

namespace
{
using emslam::bench::kittiObservation;
using emslam::stereo::StereoFrontEnd;
using emslam::stereo::StereoMatcher;

mrpt::obs::CObservationStereoImages::Ptr eurocObservation()
{
    const std::string mav = emslam::bench::dataDir() + "/euroc-v101-rest/mav0/";
    const std::string name = "1403715274312143104.png";
    cv::Mat l = cv::imread(mav + "cam0/data/" + name, cv::IMREAD_GRAYSCALE);
    cv::Mat r = cv::imread(mav + "cam1/data/" + name, cv::IMREAD_GRAYSCALE);
    if (l.empty() || r.empty())
    {
        return nullptr;
    }
    auto obs = mrpt::obs::CObservationStereoImages::Create();
    obs->imageLeft = mrpt::img::CImage(l, mrpt::img::DEEP_COPY);
    obs->imageRight = mrpt::img::CImage(r, mrpt::img::DEEP_COPY);
    obs->hasImageRight = true;
    obs->setStereoCameraParams(
        emslam::io::loadEurocCalibration(mav + "cam0/sensor.yaml", mav + "cam1/sensor.yaml"));
    return obs;
}

void runFrontEnd(
    benchmark::State& state,
    const mrpt::obs::CObservationStereoImages::Ptr& obs,
    const StereoMatcher::TParameters& p)
{
    if (!obs)
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    StereoFrontEnd fe(p);
    std::size_t points = 0;
    for (auto _ : state)
    {
        const auto f = fe.process(*obs);
        points = f.size();
        benchmark::DoNotOptimize(points);
    }
    state.counters["points"] = static_cast<double>(points);
    state.counters["fps"] =
        benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

StereoMatcher::TParameters params(const std::string& algo, int num_disp, int block)
{
    StereoMatcher::TParameters p;
    p.algorithm = algo;
    p.num_disparities = num_disp;
    p.block_size = block;
    p.max_range = 80.0;
    return p;
}

// The paper's working size: 320x240, 64 disparities.
void BM_Kitti320x240_SGBM(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(0, 320, 240), params("sgbm", 64, 5));
}
void BM_Kitti320x240_SGBM3Way(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(0, 320, 240), params("sgbm_3way", 64, 5));
}
void BM_Kitti320x240_BM(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(0, 320, 240), params("bm", 64, 9));
}
// KITTI's full resolution, 1226x370, 128 disparities (objects down to ~3 m).
void BM_KittiFull_SGBM(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(0, 0, 0), params("sgbm", 128, 5));
}
void BM_KittiFull_SGBM3Way(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(0, 0, 0), params("sgbm_3way", 128, 5));
}
void BM_KittiFull_BM(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(0, 0, 0), params("bm", 128, 9));
}
// Raw EuRoC pair: undistortion + rectification + SGBM at 752x480.
void BM_EurocRaw752x480_SGBM(benchmark::State& s)
{
    runFrontEnd(s, eurocObservation(), params("sgbm", 64, 5));
}
}  // namespace

BENCHMARK(BM_Kitti320x240_SGBM)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kitti320x240_SGBM3Way)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kitti320x240_BM)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_SGBM)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_SGBM3Way)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_BM)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EurocRaw752x480_SGBM)->Unit(benchmark::kMillisecond);

EMSLAM_BENCHMARK_MAIN();
