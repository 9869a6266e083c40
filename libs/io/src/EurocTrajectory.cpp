// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DataFile.h>
#include <emslam/io/EurocTrajectory.h>
#include <emslam/io/TextParsing.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/math/CQuaternion.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <string_view>
#include <vector>

namespace emslam::io
{
namespace
{
std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

/** Whether a header line puts the quaternion's w before its x; empty if it
 * names neither. */
std::optional<bool> headerSaysWFirst(const std::string& header)
{
    const auto fields = splitCommaFields(lower(header));
    std::optional<std::size_t> w, x;
    for (std::size_t i = 0; i < fields.size(); i++)
    {
        const auto& f = fields[i];
        const auto name = f.substr(0, f.find(' '));  // drop a unit: "q_rs_w []"
        if (!w && (name == "q_rs_w" || name == "qw"))
        {
            w = i;
        }
        if (!x && (name == "q_rs_x" || name == "qx"))
        {
            x = i;
        }
    }
    if (!w || !x)
    {
        return std::nullopt;
    }
    return *w < *x;
}
}  // namespace

TumTrajectory EurocTrajectory::load(const std::string& file)
{
    auto f = openTextFile(file, "EuRoC ground-truth file");
    TumTrajectory out;
    std::optional<bool> w_first;
    forEachNonBlankLine(
        f,
        [&](const std::string& line, std::size_t line_no)
        {
            if (isCommentOrBlank(line))
            {
                if (!w_first)
                {
                    w_first = headerSaysWFirst(std::string(trimmed(line).substr(1)));
                }
                return;
            }
            const auto fields = splitCommaFields(line);
            if (fields.size() < 8)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: expected at least 8 comma-separated fields (timestamp_ns, position, "
                    "quaternion), got %zu in %s",
                    file.c_str(), line_no, fields.size(), quotedExcerpt(line).c_str());
            }
            std::int64_t t_ns = 0;
            if (!parseNanoseconds(fields[0], t_ns))
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: timestamp %s is not an integer number of nanoseconds in [0, "
                    "9223372036854775807]",
                    file.c_str(), line_no, quotedExcerpt(fields[0]).c_str());
            }
            double v[7];
            bool ok = true;
            for (int k = 0; k < 7 && ok; k++)
            {
                ok = parseDouble(fields[k + 1], v[k]) && std::isfinite(v[k]);
            }
            if (!ok)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: not a number (7 finite numbers after the timestamp expected) "
                    "in %s",
                    file.c_str(), line_no, quotedExcerpt(line).c_str());
            }
            const bool wf = w_first.value_or(fields.size() != 8);
            const double qw = wf ? v[3] : v[6];
            const double qx = wf ? v[4] : v[3];
            const double qy = wf ? v[5] : v[4];
            const double qz = wf ? v[6] : v[5];
            const double norm = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
            if (norm < 1e-9)
            {
                THROW_EXCEPTION_FMT("%s:%zu: zero quaternion", file.c_str(), line_no);
            }
            const mrpt::math::CQuaternionDouble q(qw / norm, qx / norm, qy / norm, qz / norm);
            // Whole seconds and the rest apart: the double keeps more of the nanoseconds.
            const double t = static_cast<double>(t_ns / 1000000000) +
                             1e-9 * static_cast<double>(t_ns % 1000000000);
            out.add(t, mrpt::poses::CPose3D(q, v[0], v[1], v[2]));
        },
        file);
    if (f.bad())
    {
        THROW_EXCEPTION_FMT("Error reading EuRoC ground-truth file '%s'", file.c_str());
    }
    if (out.empty())
    {
        THROW_EXCEPTION_FMT("EuRoC ground-truth file '%s' holds no pose", file.c_str());
    }
    return out;
}

}  // namespace emslam::io
