// SPDX-License-Identifier: BSD-3-Clause
// Per-frame cost of the stereo front-end (rectification + disparity + 3D) on
// real images, single-threaded. Run: bench_stereo_frontend [--benchmark_filter=...]
// Needs the KITTI / EuRoC excerpts (EMSLAM_TEST_DATA, default ../shared/data).
#include <emslam/stereo/CalibrationReaders.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/system/filesystem.h>

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

namespace
{
using emslam::stereo::StereoFrontEnd;
using emslam::stereo::StereoMatcher;

std::string dataDir()
{
    const char* env = std::getenv("EMSLAM_TEST_DATA");
    return (env != nullptr && *env != '\0') ? env : EMSLAM_TEST_DATA_DEFAULT;
}

/** A rectified stereo observation from KITTI 06 frame 0, optionally cropped to
 * 4:3 and resized (the paper worked at 320x240). Null if the data is absent. */
mrpt::obs::CObservationStereoImages::Ptr kittiObservation(int width, int height)
{
    const std::string seq = dataDir() + "/kitti-odometry/sequences/06/";
    cv::Mat l = cv::imread(seq + "image_0/000000.png", cv::IMREAD_GRAYSCALE);
    cv::Mat r = cv::imread(seq + "image_1/000000.png", cv::IMREAD_GRAYSCALE);
    if (l.empty() || r.empty())
    {
        return nullptr;
    }
    auto cam = emslam::stereo::loadKittiCalibration(seq + "calib.txt", l.cols, l.rows);
    if (width > 0)
    {
        // Central 4:3 crop, then resize: same optics, fewer pixels.
        const int cw = l.rows * width / height;
        const cv::Rect roi((l.cols - cw) / 2, 0, cw, l.rows);
        const double s = static_cast<double>(width) / cw;
        cv::resize(l(roi), l, cv::Size(width, height), 0, 0, cv::INTER_AREA);
        cv::resize(r(roi), r, cv::Size(width, height), 0, 0, cv::INTER_AREA);
        for (auto* c : {&cam.leftCamera, &cam.rightCamera})
        {
            c->ncols = width;
            c->nrows = height;
            c->setIntrinsicParamsFromValues(
                c->fx() * s, c->fy() * s, (c->cx() - roi.x + 0.5) * s - 0.5,
                (c->cy() + 0.5) * s - 0.5);
        }
    }
    auto obs = mrpt::obs::CObservationStereoImages::Create();
    obs->imageLeft = mrpt::img::CImage(l, mrpt::img::DEEP_COPY);
    obs->imageRight = mrpt::img::CImage(r, mrpt::img::DEEP_COPY);
    obs->hasImageRight = true;
    obs->setStereoCameraParams(cam);
    return obs;
}

mrpt::obs::CObservationStereoImages::Ptr eurocObservation()
{
    const std::string mav = dataDir() + "/euroc-v101-rest/mav0/";
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
        emslam::stereo::loadEurocCalibration(mav + "cam0/sensor.yaml", mav + "cam1/sensor.yaml"));
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
    runFrontEnd(s, kittiObservation(320, 240), params("sgbm", 64, 5));
}
void BM_Kitti320x240_SGBM3Way(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(320, 240), params("sgbm_3way", 64, 5));
}
void BM_Kitti320x240_BM(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(320, 240), params("bm", 64, 9));
}
// KITTI's full resolution, 1226x370, 128 disparities (objects down to ~3 m).
void BM_KittiFull_SGBM(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(0, 0), params("sgbm", 128, 5));
}
void BM_KittiFull_SGBM3Way(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(0, 0), params("sgbm_3way", 128, 5));
}
void BM_KittiFull_BM(benchmark::State& s)
{
    runFrontEnd(s, kittiObservation(0, 0), params("bm", 128, 9));
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

int main(int argc, char** argv)
{
    cv::setNumThreads(1);  // the target is per frame on one core
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv))
    {
        return 1;
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
