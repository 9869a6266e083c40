// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DataFile.h>
#include <emslam/io/TextParsing.h>
#include <emslam/io/TrajectoryFormat.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace emslam::io
{
namespace
{
/** Smallest nanosecond timestamp taken as one (1e12 ns: 1000 s after 1970). */
constexpr std::int64_t MIN_NS_TIMESTAMP = 1000000000000;
}  // namespace

TrajectoryFormat parseTrajectoryFormat(const std::string& s)
{
    std::string l = s;
    std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::tolower(c); });
    for (const auto f :
         {TrajectoryFormat::Auto, TrajectoryFormat::Tum, TrajectoryFormat::Kitti,
          TrajectoryFormat::Euroc})
    {
        if (l == trajectoryFormatName(f))
        {
            return f;
        }
    }
    throw std::invalid_argument(
        "unknown trajectory format '" + s + "': expected auto, tum, kitti or euroc");
}

std::string trajectoryFormatName(TrajectoryFormat f)
{
    switch (f)
    {
        case TrajectoryFormat::Tum:
            return "tum";
        case TrajectoryFormat::Kitti:
            return "kitti";
        case TrajectoryFormat::Euroc:
            return "euroc";
        case TrajectoryFormat::Auto:
        default:
            return "auto";
    }
}

TrajectoryFormat detectTrajectoryFormat(const std::string& file)
{
    auto f = openTextFile(file, "trajectory file");
    std::string line;
    std::size_t line_no = 0;
    std::vector<double> v;
    while (readBoundedLine(f, line, file, line_no + 1))
    {
        ++line_no;
        if (isBlank(line))
        {
            continue;
        }
        if (isCommentOrBlank(line))
        {
            if (line.find("p_RS_R_x") != std::string::npos ||
                line.find("q_RS_w") != std::string::npos)
            {
                return TrajectoryFormat::Euroc;
            }
            continue;
        }
        const auto comma = line.find(',');
        if (comma != std::string::npos)
        {
            std::int64_t t_ns = 0;
            if (parseNanoseconds(trimmed(std::string_view(line).substr(0, comma)), t_ns) &&
                t_ns >= MIN_NS_TIMESTAMP)
            {
                return TrajectoryFormat::Euroc;
            }
        }
        const bool numbers = parseNumbers(line, v, comma != std::string::npos ? " \t,\r" : " \t\r");
        if (numbers && v.size() == 12)
        {
            return TrajectoryFormat::Kitti;
        }
        if (numbers && v.size() == 8)
        {
            return TrajectoryFormat::Tum;
        }
        THROW_EXCEPTION_FMT(
            "%s:%zu: cannot tell the trajectory format of %s: expected 8 numbers (TUM: t tx "
            "ty tz qx qy qz qw), 12 numbers (KITTI: a 3x4 row-major pose) or a EuRoC CSV row "
            "(timestamp_ns,x,y,z,...)",
            file.c_str(), line_no, quotedExcerpt(line).c_str());
    }
    THROW_EXCEPTION_FMT("Trajectory file '%s' has no poses", file.c_str());
}

}  // namespace emslam::io
