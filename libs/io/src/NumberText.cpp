// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/NumberText.h>

#include <charconv>

namespace emslam::io
{
std::string shortestFixed(double v)
{
    char buf[400];  // the longest fixed form of a double (a denormal) fits
    const auto res = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed);
    return std::string(buf, res.ptr);
}

std::string shortestText(double v)
{
    char buf[64];  // the shortest form of any double fits
    const auto res = std::to_chars(buf, buf + sizeof(buf), v);
    return std::string(buf, res.ptr);
}

}  // namespace emslam::io
