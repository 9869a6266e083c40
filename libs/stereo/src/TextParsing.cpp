// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/stereo/TextParsing.h>

#include <charconv>
#include <system_error>

namespace emslam::stereo
{
namespace
{
constexpr std::string_view BLANKS = " \t\r\n";

/** True if `[first, last)` was consumed entirely by a successful from_chars. */
bool consumedAll(const std::from_chars_result& res, const char* last)
{
    return res.ec == std::errc() && res.ptr == last;
}
}  // namespace

std::string_view trimmed(std::string_view s)
{
    const auto first = s.find_first_not_of(BLANKS);
    if (first == std::string_view::npos)
    {
        return {};
    }
    const auto last = s.find_last_not_of(BLANKS);
    return s.substr(first, last - first + 1);
}

bool isBlank(std::string_view line)
{
    return line.find_first_not_of(BLANKS) == std::string_view::npos;
}

bool isCommentOrBlank(std::string_view line)
{
    const auto first = line.find_first_not_of(BLANKS);
    return first == std::string_view::npos || line[first] == '#';
}

bool parseDouble(std::string_view token, double& v)
{
    if (!token.empty() && token.front() == '+')
    {
        token.remove_prefix(1);  // from_chars rejects a leading '+'
    }
    const char* last = token.data() + token.size();
    return consumedAll(std::from_chars(token.data(), last, v), last);
}

bool parseInt64(std::string_view token, std::int64_t& v)
{
    const char* last = token.data() + token.size();
    return consumedAll(std::from_chars(token.data(), last, v), last);
}

bool parseNumbers(std::string_view line, std::vector<double>& out, std::string_view separators)
{
    out.clear();
    std::size_t pos = 0;
    while ((pos = line.find_first_not_of(separators, pos)) != std::string_view::npos)
    {
        const std::size_t end = std::min(line.find_first_of(separators, pos), line.size());
        double v = 0;
        if (!parseDouble(line.substr(pos, end - pos), v))
        {
            return false;
        }
        out.push_back(v);
        pos = end;
    }
    return true;
}

}  // namespace emslam::stereo
