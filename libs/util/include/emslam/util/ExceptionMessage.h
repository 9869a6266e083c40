// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <exception>
#include <sstream>
#include <string>
#include <vector>

namespace emslam::util
{
namespace detail
{
/** `s` without leading and trailing white space. */
inline std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos)
    {
        return {};
    }
    return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}
}  // namespace detail

/** The human part of an exception's text. MRPT exceptions embed source
 * locations and a call-stack backtrace in what(); this keeps only their
 * "Message:" lines (outermost first, joined by ": "), which is what a user
 * needs to see; a std::exception that MRPT_END wrapped gives its own text
 * without MRPT's header and backtrace. Other exceptions return what()
 * trimmed.
 * \ingroup emslam_util_grp */
inline std::string shortExceptionMessage(const std::exception& e)
{
    const std::string text = e.what();
    std::vector<std::string> messages;
    std::istringstream in(text);
    std::string line;
    constexpr const char* TAG = "Message:";
    while (std::getline(in, line))
    {
        const auto pos = line.find(TAG);
        if (pos != std::string::npos)
        {
            const std::string m =
                detail::trim(line.substr(pos + std::char_traits<char>::length(TAG)));
            if (!m.empty())
            {
                messages.push_back(m);
            }
        }
    }
    if (messages.empty())
    {
        // A std::exception that MRPT_END wrapped (ExceptionWithCallBack):
        // its text comes between MRPT's header and the backtrace, untagged.
        const std::string header = "==== MRPT exception ====";
        const std::string t = detail::trim(text);
        const auto stack = t.find("Call stack backtrace:");
        if (t.compare(0, header.size(), header) == 0 && stack != std::string::npos)
        {
            return detail::trim(t.substr(header.size(), stack - header.size()));
        }
        return t;
    }
    std::string out;
    for (const auto& m : messages)
    {
        out += (out.empty() ? "" : ": ") + m;
    }
    return out;
}

}  // namespace emslam::util
