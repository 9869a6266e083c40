// SPDX-License-Identifier: BSD-3-Clause
// Trajectory files (TUM, KITTI poses + times, EuRoC CSV): loadTrajectory() as
// emslam-eval and --gt use it. The first byte picks the format (auto, TUM,
// KITTI, EuRoC); the rest is the trajectory, then, after a line "---", the
// KITTI times file.
#include "FuzzFile.h"

#include <emslam/io/TrajectoryReader.h>

#include <cstddef>
#include <cstdint>
#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    if (size == 0)
    {
        return 0;
    }
    using emslam::io::TrajectoryFormat;
    constexpr TrajectoryFormat FORMATS[] = {
        TrajectoryFormat::Auto, TrajectoryFormat::Tum, TrajectoryFormat::Kitti,
        TrajectoryFormat::Euroc};
    emslam::io::TrajectoryReadOptions options;
    options.format = FORMATS[data[0] % 4];
    const auto [poses, times] =
        emslam::fuzz::splitAtLine(emslam::fuzz::asText(data + 1, size - 1), "---");
    const auto& folder = emslam::fuzz::FuzzFolder::instance();
    const std::string file = folder.write("trajectory.txt", poses);
    options.times_file = folder.write("trajectory_times.txt", times);
    try
    {
        const auto loaded = emslam::io::loadTrajectory(file, options);
        loaded.missingTimesMessage(file);
    }
    catch (const std::exception&)
    {
        // A clean error is the expected outcome of a bad file.
    }
    return 0;
}
