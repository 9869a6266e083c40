// SPDX-License-Identifier: BSD-3-Clause
// Helpers shared by the benchmarks/*.cpp programs: the test-data folder, the
// KITTI 06 stereo pairs they time, and their common main().
#pragma once

#include <mrpt/obs/CObservationStereoImages.h>

#include <string>

namespace emslam::bench
{
/** The test-data folder: $EMSLAM_TEST_DATA if set and non-empty, else the
 * EMSLAM_TEST_DATA_DEFAULT given at build time. */
std::string dataDir();

/** The source tree, for its config/ files. */
std::string sourceDir();

/** A rectified stereo observation of KITTI 06 frame `index` with its
 * calibration, optionally as a central crop to the aspect ratio of
 * `width` x `height` resized to that size (same optics, fewer pixels; the
 * paper worked at 320x240), or at full size if `width` <= 0.
 * Null if the data is absent. */
mrpt::obs::CObservationStereoImages::Ptr kittiObservation(int index, int width, int height);

/** The main() of every benchmark: one OpenCV thread (the targets are per frame
 * on one core), the apps' allocator policy (emslam::slam::keepFrameBuffersInProcess),
 * then Google Benchmark's initialization and run. */
int runBenchmarks(int argc, char** argv);

}  // namespace emslam::bench

/** Defines main() as emslam::bench::runBenchmarks(). */
#define EMSLAM_BENCHMARK_MAIN()                            \
    int main(int argc, char** argv)                        \
    {                                                      \
        return ::emslam::bench::runBenchmarks(argc, argv); \
    }                                                      \
    static_assert(true, "EMSLAM_BENCHMARK_MAIN needs a ';'")
