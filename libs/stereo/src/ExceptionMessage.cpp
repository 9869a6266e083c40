// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/stereo/ExceptionMessage.h>

#include <sstream>
#include <vector>

namespace emslam::stereo
{
namespace
{
std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos)
    {
        return {};
    }
    return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}
}  // namespace

std::string shortExceptionMessage(const std::exception& e)
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
            const std::string m = trim(line.substr(pos + std::char_traits<char>::length(TAG)));
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
        const std::string t = trim(text);
        const auto stack = t.find("Call stack backtrace:");
        if (t.compare(0, header.size(), header) == 0 && stack != std::string::npos)
        {
            return trim(t.substr(header.size(), stack - header.size()));
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

}  // namespace emslam::stereo
