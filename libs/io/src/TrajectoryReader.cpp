// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/EurocTrajectory.h>
#include <emslam/io/KittiTrajectory.h>
#include <emslam/io/TrajectoryReader.h>

namespace emslam::io
{
std::string LoadedTrajectory::missingTimesMessage(const std::string& file) const
{
    std::string tried;
    for (const auto& c : times_candidates)
    {
        tried += (tried.empty() ? "'" : ", '") + c + "'";
    }
    return "KITTI poses file '" + file + "' has no times file (none of " + tried + " exists)";
}

LoadedTrajectory loadTrajectory(const std::string& file, const TrajectoryReadOptions& o)
{
    LoadedTrajectory out;
    out.format = o.format == TrajectoryFormat::Auto ? detectTrajectoryFormat(file) : o.format;
    switch (out.format)
    {
        case TrajectoryFormat::Kitti:
        {
            out.times_file =
                o.times_file.empty() ? KittiTrajectory::findTimesFile(file) : o.times_file;
            if (!out.times_file.empty())
            {
                out.trajectory = KittiTrajectory::load(file, out.times_file, o.kitti_time_offset);
                break;
            }
            out.timed = false;
            out.times_candidates = KittiTrajectory::timesFileCandidates(file);
            const auto poses = KittiTrajectory::readPoses(file);
            for (std::size_t i = 0; i < poses.size(); i++)
            {
                out.trajectory.add(static_cast<double>(i), poses[i]);
            }
            break;
        }
        case TrajectoryFormat::Euroc:
            out.trajectory = EurocTrajectory::load(file);
            break;
        case TrajectoryFormat::Tum:
        case TrajectoryFormat::Auto:
        default:
            out.format = TrajectoryFormat::Tum;
            out.trajectory.loadFromFile(file);
            break;
    }
    return out;
}

}  // namespace emslam::io
