// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DataFile.h>
#include <emslam/io/NumberText.h>
#include <emslam/io/OutputFile.h>
#include <emslam/io/TextParsing.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/math/CQuaternion.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <ostream>
#include <sstream>

namespace emslam::io
{
std::string formatTimestamp(double t)
{
    // UNIX times need 10 integer digits: the shortest form would be "1.7e+09"
    // for whole seconds. The shortest fixed form reads back to the same double;
    // padded to nine decimals it reads "...200000000", not the double's
    // "...200000048" noise.
    constexpr std::size_t DECIMALS = 9;
    std::string s = shortestFixed(t);
    const auto dot = s.find('.');
    const std::size_t decimals = dot == std::string::npos ? 0 : s.size() - dot - 1;
    if (decimals > DECIMALS)
    {
        char buf[400];
        std::snprintf(buf, sizeof(buf), "%.9f", t);
        return buf;
    }
    if (dot == std::string::npos)
    {
        s += '.';
    }
    s.append(DECIMALS - decimals, '0');
    return s;
}

std::string TumTrajectory::formatLine(const TumPose& p)
{
    mrpt::math::CQuaternionDouble q;
    p.pose.getAsQuaternion(q);
    q.ensurePositiveRealPart();
    std::string s = formatTimestamp(p.t);
    for (const double v : {p.pose.x(), p.pose.y(), p.pose.z(), q.x(), q.y(), q.z(), q.r()})
    {
        s += ' ';
        s += shortestFixed(v);
    }
    return s;
}

void TumTrajectory::writeTo(std::ostream& out) const
{
    for (const auto& p : poses)
    {
        out << formatLine(p) << '\n';
    }
}

void TumTrajectory::saveToFile(const std::string& file) const
{
    OutputFile f(file);
    writeTo(f.text());
    f.close();
}

void TumTrajectory::loadFromFile(const std::string& file)
{
    auto f = openTextFile(file, "trajectory file");
    std::vector<TumPose> out;
    std::vector<double> v;
    forEachDataLine(
        f,
        [&](const std::string& line, std::size_t line_no)
        {
            if (!parseNumbers(line, v, " \t,\r") || v.size() != 8)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: expected 8 numbers 'timestamp tx ty tz qx qy qz qw', got %s",
                    file.c_str(), line_no, quotedExcerpt(line).c_str());
            }
            for (const double x : v)
            {
                if (!std::isfinite(x))
                {
                    THROW_EXCEPTION_FMT(
                        "%s:%zu: non-finite number in %s", file.c_str(), line_no,
                        quotedExcerpt(line).c_str());
                }
            }
            const double norm = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
            if (norm < 1e-9)
            {
                THROW_EXCEPTION_FMT("%s:%zu: zero quaternion", file.c_str(), line_no);
            }
            const mrpt::math::CQuaternionDouble q(
                v[7] / norm, v[4] / norm, v[5] / norm, v[6] / norm);
            out.push_back({v[0], mrpt::poses::CPose3D(q, v[1], v[2], v[3])});
        },
        file);
    if (f.bad())
    {
        THROW_EXCEPTION_FMT("Error reading trajectory file '%s'", file.c_str());
    }
    poses = std::move(out);
}

TumTrajectory TumTrajectory::fromFile(const std::string& file)
{
    TumTrajectory t;
    t.loadFromFile(file);
    return t;
}

}  // namespace emslam::io
