// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/NumberText.h>
#include <emslam/io/TrajectoryInput.h>
#include <emslam/util/ExceptionMessage.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace emslam::io
{
emslam::io::LoadedTrajectory loadTrajectoryInput(
    const std::string& file,
    const std::string& what,
    const emslam::io::TrajectoryReadOptions& options)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(file, ec))
    {
        throw std::runtime_error(what + " file '" + file + "' does not exist");
    }
    if (fs::is_directory(file, ec))
    {
        throw std::runtime_error(what + " file '" + file + "' is a directory");
    }
    emslam::io::LoadedTrajectory t;
    try
    {
        t = emslam::io::loadTrajectory(file, options);
    }
    catch (const std::exception& e)
    {
        // The reader's message names the file and line; say which input it was.
        throw std::runtime_error(
            "cannot read " + what + ": " + emslam::util::shortExceptionMessage(e));
    }
    if (t.trajectory.empty())
    {
        throw std::runtime_error(what + " file '" + file + "' has no poses");
    }
    requirePlausiblePositions(t.trajectory, file, what);
    return t;
}

void requirePlausiblePositions(
    const emslam::io::TumTrajectory& t, const std::string& file, const std::string& what)
{
    for (std::size_t i = 0; i < t.poses.size(); ++i)
    {
        const auto& p = t.poses[i].pose;
        for (const double c : {p.x(), p.y(), p.z()})
        {
            if (!(std::abs(c) <= MAX_POSITION_M))
            {
                throw std::runtime_error(
                    what + " file '" + file + "': pose " + std::to_string(i + 1) + " (t = " +
                    shortestFixed(t.poses[i].t) + " s) lies at (" + shortestText(p.x()) + ", " +
                    shortestText(p.y()) + ", " + shortestText(p.z()) + ") m; a coordinate beyond " +
                    shortestText(MAX_POSITION_M) + " m is no trajectory (wrong columns or units?)");
            }
        }
    }
}

void requireTimes(
    const emslam::io::LoadedTrajectory& t,
    const std::string& file,
    const std::string& what,
    const std::string& times_option)
{
    if (!t.timed)
    {
        throw std::runtime_error(
            what + ": " + t.missingTimesMessage(file) + "; give one with " + times_option +
            " FILE");
    }
}

void requireComparableTimes(
    const emslam::io::LoadedTrajectory& gt,
    const std::string& gt_file,
    const emslam::io::LoadedTrajectory& est,
    const std::string& est_file)
{
    if (gt.timed == est.timed)
    {
        return;
    }
    const std::string pairing =
        " (or give both as KITTI poses without times, to pair them line by line)";
    if (!gt.timed)
    {
        throw std::runtime_error(
            "ground truth: " + gt.missingTimesMessage(gt_file) + "; give one with --gt-times FILE" +
            pairing);
    }
    throw std::runtime_error(
        "estimate: " + est.missingTimesMessage(est_file) + "; give one with --est-times FILE" +
        pairing);
}

}  // namespace emslam::io
