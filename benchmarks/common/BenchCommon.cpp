// SPDX-License-Identifier: BSD-3-Clause
#include "BenchCommon.h"

#include <emslam/io/CalibrationFiles.h>
#include <emslam/slam/FrameMemoryPolicy.h>

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace emslam::bench
{
std::string dataDir()
{
    const char* env = std::getenv("EMSLAM_TEST_DATA");
    return (env != nullptr && *env != '\0') ? env : EMSLAM_TEST_DATA_DEFAULT;
}

std::string sourceDir()
{
    return EMSLAM_SOURCE_DIR;
}

mrpt::obs::CObservationStereoImages::Ptr kittiObservation(int index, int width, int height)
{
    const std::string seq = dataDir() + "/kitti-odometry/sequences/06/";
    char name[16];
    std::snprintf(name, sizeof(name), "%06d.png", index);
    cv::Mat l = cv::imread(seq + "image_0/" + name, cv::IMREAD_GRAYSCALE);
    cv::Mat r = cv::imread(seq + "image_1/" + name, cv::IMREAD_GRAYSCALE);
    if (l.empty() || r.empty())
    {
        return nullptr;
    }
    auto cam = emslam::io::loadKittiCalibration(seq + "calib.txt", l.cols, l.rows);
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

int runBenchmarks(int argc, char** argv)
{
    cv::setNumThreads(1);                       // the target is per frame on one core
    emslam::slam::keepFrameBuffersInProcess();  // as the apps run
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv))
    {
        return 1;
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}

}  // namespace emslam::bench
