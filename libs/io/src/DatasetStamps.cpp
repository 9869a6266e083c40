// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DatasetStamps.h>
#include <emslam/io/TextParsing.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace emslam::io
{
namespace
{
[[noreturn]] void refuse(
    const std::string& file, std::size_t line_no, std::string_view token, const std::string& reason)
{
    throw std::runtime_error(
        file + ":" + std::to_string(line_no) + ": timestamp " + quotedExcerpt(token) + " " +
        reason);
}

bool allDigits(std::string_view s)
{
    return std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

std::string implausibleNs()
{
    return "is not a plausible time: expected nanoseconds since 1970-01-01 UTC in [" +
           std::to_string(MIN_STAMP_NS) + ", " + std::to_string(MAX_STAMP_NS) +
           "] (MRPT reads 0 as \"no time\"; the upper bound is 2100-01-01)";
}
}  // namespace

std::int64_t parseImageStampNs(std::string_view token, const std::string& file, std::size_t line_no)
{
    std::string_view whole = token;
    std::string_view fraction;
    if (const auto dot = token.find('.'); dot != std::string_view::npos)
    {
        whole = token.substr(0, dot);
        fraction = token.substr(dot + 1);
    }
    const std::string_view digits =
        !whole.empty() && whole.front() == '-' ? whole.substr(1) : whole;
    if (digits.empty() || !allDigits(digits) || !allDigits(fraction))
    {
        refuse(file, line_no, token, "is not an integer number of nanoseconds");
    }
    if (fraction.find_first_not_of('0') != std::string_view::npos)
    {
        refuse(
            file, line_no, token,
            "has a fraction of a nanosecond: expected whole nanoseconds (a '.000' fraction is "
            "allowed)");
    }
    std::int64_t t = 0;
    // Digits that do not fit in 64 bits are out of range as well.
    if (!parseInt64(whole, t) || t < MIN_STAMP_NS || t > MAX_STAMP_NS)
    {
        refuse(file, line_no, token, implausibleNs());
    }
    return t;
}

void requirePlausibleStampSeconds(
    double t, std::string_view token, const std::string& file, std::size_t line_no)
{
    constexpr double MIN_S = 1e-9 * static_cast<double>(MIN_STAMP_NS);
    constexpr double MAX_S = 1e-9 * static_cast<double>(MAX_STAMP_NS);
    if (!(t >= MIN_S && t <= MAX_S))  // NaN fails too
    {
        refuse(
            file, line_no, token,
            "is not a plausible time: expected seconds since 1970-01-01 UTC in [1e-07, "
            "4102444800] (MRPT reads 0 as \"no time\"; the upper bound is 2100-01-01)");
    }
}

template <typename Stamp>
IncreasingStamps<Stamp>::IncreasingStamps(std::string file) : m_file(std::move(file))
{
}

template <typename Stamp>
void IncreasingStamps<Stamp>::add(Stamp t, std::string_view token, std::size_t line_no)
{
    if (m_last && !(t > *m_last))
    {
        const std::string previous = "(line " + std::to_string(m_last_line) + ")";
        refuse(
            m_file, line_no, token,
            (t == *m_last
                 ? "repeats the previous one " + previous
                 : "is before the previous one " + quotedExcerpt(m_last_token) + " " + previous) +
                ": timestamps must increase strictly");
    }
    m_last = t;
    m_last_token.assign(token);
    m_last_line = line_no;
}

template class IncreasingStamps<std::int64_t>;
template class IncreasingStamps<double>;

}  // namespace emslam::io
