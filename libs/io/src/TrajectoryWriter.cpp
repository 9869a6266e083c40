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

std::vector<std::string> trajectoryFiles(const std::string& file, TrajectoryOutput output)
{
    std::vector<std::string> files;
    std::string kitti = file;
    if (output != TrajectoryOutput::Kitti)
    {
        files.push_back(file);
        kitti = kittiFileBeside(file);
    }
    if (output != TrajectoryOutput::Tum)
    {
        files.push_back(kitti);
        files.push_back(KittiTrajectory::timesFileFor(kitti));
    }
    return files;
}

std::vector<std::string> saveTrajectory(
    const TumTrajectory& t, const std::string& file, TrajectoryOutput output)
{
    const std::vector<std::string> files = trajectoryFiles(file, output);
    if (output == TrajectoryOutput::Kitti)
    {
        KittiTrajectory::save(t, files[0], files[1]);
        return files;
    }
    t.saveToFile(files[0]);
    if (output == TrajectoryOutput::Both)
    {
        KittiTrajectory::save(t, files[1], files[2]);
    }
    return files;
}

}  // namespace emslam::io
