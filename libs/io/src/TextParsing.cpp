// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DataFile.h>
#include <emslam/io/TextParsing.h>

#include <algorithm>
#include <charconv>
#include <istream>
#include <system_error>

namespace emslam::io
{
namespace
{
constexpr std::string_view BLANKS = " \t\r\n";

/** Parses all of a non-empty `token` with std::from_chars; sets `v` only on success. */
template <typename T>
bool parseWhole(std::string_view token, T& v)
{
    if (token.empty())
    {
        return false;
    }
    const char* last = token.data() + token.size();
    T x{};
    const auto res = std::from_chars(token.data(), last, x);
    if (res.ec != std::errc() || res.ptr != last)
    {
        return false;
    }
    v = x;
    return true;
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

std::vector<std::string> splitCommaFields(std::string_view line)
{
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true)
    {
        const auto p = line.find(',', start);
        out.emplace_back(trimmed(line.substr(start, p == std::string_view::npos ? p : p - start)));
        if (p == std::string_view::npos)
        {
            return out;
        }
        start = p + 1;
    }
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

namespace
{
void forEachLineUnless(
    std::istream& in,
    bool (*skip)(std::string_view),
    const std::function<void(const std::string& line, std::size_t line_no)>& on_line,
    const std::string& source)
{
    std::string line;
    std::size_t line_no = 0;
    while (readBoundedLine(in, line, source, line_no + 1))
    {
        ++line_no;
        if (!skip(line))
        {
            on_line(line, line_no);
        }
    }
}
}  // namespace

void forEachDataLine(
    std::istream& in,
    const std::function<void(const std::string& line, std::size_t line_no)>& on_line,
    const std::string& source)
{
    forEachLineUnless(in, &isCommentOrBlank, on_line, source);
}

void forEachNonBlankLine(
    std::istream& in,
    const std::function<void(const std::string& line, std::size_t line_no)>& on_line,
    const std::string& source)
{
    forEachLineUnless(in, &isBlank, on_line, source);
}

bool parseDouble(std::string_view token, double& v)
{
    if (!token.empty() && token.front() == '+')
    {
        token.remove_prefix(1);  // from_chars rejects a leading '+'
    }
    return parseWhole(token, v);
}

bool parseInt64(std::string_view token, std::int64_t& v)
{
    return parseWhole(token, v);
}

bool parseNanoseconds(std::string_view token, std::int64_t& v)
{
    const auto dot = token.find('.');
    if (dot != std::string_view::npos)
    {
        const std::string_view frac = token.substr(dot + 1);
        // Only zeros: a fraction of a nanosecond would be dropped silently.
        if (!std::all_of(frac.begin(), frac.end(), [](char c) { return c == '0'; }))
        {
            return false;
        }
        token = token.substr(0, dot);
    }
    // Negative stamps are refused so that differences of two stamps cannot overflow.
    if (!token.empty() && token.front() == '-')
    {
        return false;
    }
    return parseInt64(token, v);
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

std::string quotedExcerpt(std::string_view text)
{
    if (text.size() <= MAX_QUOTED_BYTES)
    {
        return "'" + std::string(text) + "'";
    }
    std::size_t n = MAX_QUOTED_BYTES;
    // Back off over UTF-8 continuation bytes (10xxxxxx) so that no character
    // is split; a character has at most 3 of them.
    while (n + 3 > MAX_QUOTED_BYTES && (static_cast<unsigned char>(text[n]) & 0xC0U) == 0x80U)
    {
        --n;
    }
    return "'" + std::string(text.substr(0, n)) + "\xE2\x80\xA6' (" + std::to_string(text.size()) +
           " bytes)";
}

}  // namespace emslam::io
