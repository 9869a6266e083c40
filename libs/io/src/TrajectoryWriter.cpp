// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/KittiTrajectory.h>
#include <emslam/io/TrajectoryWriter.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

namespace emslam::io
{
TrajectoryOutput parseTrajectoryOutput(const std::string& s)
{
    std::string l = s;
    std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::tolower(c); });
    if (l == "tum")
    {
        return TrajectoryOutput::Tum;
    }
    if (l == "kitti")
    {
        return TrajectoryOutput::Kitti;
    }
    if (l == "both")
    {
        return TrajectoryOutput::Both;
    }
    throw std::invalid_argument(
        "unknown trajectory output format '" + s + "': expected tum, kitti or both");
}

std::string kittiFileBeside(const std::string& tum_file)
{
    const std::filesystem::path p(tum_file);
    return (p.parent_path() / (p.stem().string() + "_kitti.txt")).string();
}

std::vector<std::string> saveTrajectory(
    const TumTrajectory& t, const std::string& file, TrajectoryOutput output)
{
    std::vector<std::string> written;
    std::string kitti = file;
    if (output != TrajectoryOutput::Kitti)
    {
        t.saveToFile(file);
        written.push_back(file);
        kitti = kittiFileBeside(file);
    }
    if (output != TrajectoryOutput::Tum)
    {
        const std::string times = KittiTrajectory::timesFileFor(kitti);
        KittiTrajectory::save(t, kitti, times);
        written.push_back(kitti);
        written.push_back(times);
    }
    return written;
}

}  // namespace emslam::io
