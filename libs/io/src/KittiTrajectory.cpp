// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DataFile.h>
#include <emslam/io/KittiTrajectory.h>
#include <emslam/io/NumberText.h>
#include <emslam/io/OutputFile.h>
#include <emslam/io/TextParsing.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/math/CMatrixFixed.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace emslam::io
{
namespace
{
std::ifstream openForReading(const std::string& file, const char* what)
{
    return openTextFile(file, std::string("KITTI ") + what + " file");
}

/** Writes `text` to `file`, throwing naming it if it cannot. */
void writeText(const std::string& file, const std::string& text)
{
    OutputFile f(file);
    f.text() << text;
    f.close();
}
}  // namespace

std::vector<mrpt::poses::CPose3D> KittiTrajectory::readPoses(const std::string& file)
{
    auto f = openForReading(file, "poses");
    std::vector<mrpt::poses::CPose3D> poses;
    std::vector<double> v;
    forEachNonBlankLine(
        f,
        [&](const std::string& line, std::size_t line_no)
        {
            if (!parseNumbers(line, v) || v.size() != 12)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: expected 12 numbers (a 3x4 row-major pose matrix), got %s",
                    file.c_str(), line_no, quotedExcerpt(line).c_str());
            }
            Eigen::Matrix3d M;
            mrpt::math::CVectorFixedDouble<3> t;
            for (int r = 0; r < 3; r++)
            {
                for (int c = 0; c < 3; c++)
                {
                    M(r, c) = v[4 * r + c];
                }
                t[r] = v[4 * r + 3];
            }
            if (!M.allFinite() || !std::isfinite(t[0]) || !std::isfinite(t[1]) ||
                !std::isfinite(t[2]))
            {
                THROW_EXCEPTION_FMT("%s:%zu: non-finite number", file.c_str(), line_no);
            }
            // Nearest rotation (the file rounds to 7 digits): U * V^T of the SVD.
            const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
                M, Eigen::ComputeFullU | Eigen::ComputeFullV);
            const Eigen::Matrix3d Rn = svd.matrixU() * svd.matrixV().transpose();
            if (Rn.determinant() < 0 || (Rn - M).norm() > 1e-3)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: the 3x3 part is not a rotation matrix", file.c_str(), line_no);
            }
            mrpt::math::CMatrixDouble33 R;
            R.asEigen() = Rn;
            poses.emplace_back(R, t);
        },
        file);
    if (f.bad())
    {
        THROW_EXCEPTION_FMT("Error reading KITTI poses file '%s'", file.c_str());
    }
    if (poses.empty())
    {
        THROW_EXCEPTION_FMT("KITTI poses file '%s' holds no pose", file.c_str());
    }
    return poses;
}

std::vector<double> KittiTrajectory::readTimes(const std::string& file)
{
    auto f = openForReading(file, "timestamps");
    std::vector<double> times;
    std::vector<double> v;
    forEachNonBlankLine(
        f,
        [&](const std::string& line, std::size_t line_no)
        {
            if (!parseNumbers(line, v) || v.size() != 1)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: expected one timestamp [s], got %s", file.c_str(), line_no,
                    quotedExcerpt(line).c_str());
            }
            // Finite, in a range a clock can hold (1e10 s: year 2286), increasing.
            if (!std::isfinite(v[0]) || v[0] < 0 || v[0] >= 1e10)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: timestamp %s must be a finite number of seconds in [0, 1e10)",
                    file.c_str(), line_no, quotedExcerpt(line).c_str());
            }
            if (!times.empty() && !(v[0] > times.back()))
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: timestamp %.9g does not follow the previous one (%.9g): "
                    "times must increase",
                    file.c_str(), line_no, v[0], times.back());
            }
            times.push_back(v[0]);
        },
        file);
    if (times.empty())
    {
        THROW_EXCEPTION_FMT("KITTI timestamps file '%s' is empty", file.c_str());
    }
    return times;
}

TumTrajectory KittiTrajectory::load(
    const std::string& poses_file, const std::string& times_file, double time_offset)
{
    const auto poses = readPoses(poses_file);
    const auto times = readTimes(times_file);
    if (poses.size() != times.size())
    {
        THROW_EXCEPTION_FMT(
            "KITTI poses file '%s' has %zu poses but its times file '%s' has %zu timestamps",
            poses_file.c_str(), poses.size(), times_file.c_str(), times.size());
    }
    TumTrajectory t;
    t.poses.reserve(poses.size());
    for (std::size_t i = 0; i < poses.size(); i++)
    {
        const double ti = times[i] < RELATIVE_TIME_LIMIT ? time_offset + times[i] : times[i];
        t.add(ti, poses[i]);
    }
    return t;
}

std::string KittiTrajectory::formatLine(const mrpt::poses::CPose3D& T)
{
    const auto M = T.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    std::string s;
    for (int r = 0; r < 3; r++)
    {
        for (int c = 0; c < 4; c++)
        {
            if (!s.empty())
            {
                s += ' ';
            }
            s += shortestFixed(M(r, c));
        }
    }
    return s;
}

void KittiTrajectory::save(
    const TumTrajectory& t, const std::string& poses_file, const std::string& times_file)
{
    std::string poses, times;
    for (const auto& p : t.poses)
    {
        poses += formatLine(p.pose) + '\n';
        times += formatTimestamp(p.t) + '\n';
    }
    writeText(poses_file, poses);
    writeText(times_file, times);
}

std::string KittiTrajectory::timesFileFor(const std::string& poses_file)
{
    const fs::path p(poses_file);
    std::string stem = p.stem().string();
    const std::string suffix = "_kitti";
    if (stem.size() > suffix.size() &&
        stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0)
    {
        stem.erase(stem.size() - suffix.size());
    }
    return (p.parent_path() / (stem + "_times.txt")).string();
}

std::vector<std::string> KittiTrajectory::timesFileCandidates(const std::string& poses_file)
{
    const fs::path p(poses_file);
    std::vector<std::string> out{timesFileFor(poses_file)};
    const fs::path dir = p.parent_path();
    if (dir.filename() == "poses")
    {
        out.push_back((dir.parent_path() / "sequences" / p.stem() / "times.txt").string());
    }
    out.push_back((dir / "times.txt").string());
    return out;
}

std::string KittiTrajectory::findTimesFile(const std::string& poses_file)
{
    for (const auto& c : timesFileCandidates(poses_file))
    {
        std::error_code ec;
        if (fs::is_regular_file(c, ec))
        {
            return c;
        }
    }
    return {};
}

}  // namespace emslam::io
