// SPDX-License-Identifier: BSD-3-Clause
#include "ConfigCount.h"

#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <stdexcept>

namespace emslam::hwdrivers
{
std::size_t parseCount(
    const std::string& raw,
    const std::string& section,
    const std::string& key,
    std::size_t fallback)
{
    const std::string text = mrpt::system::trim(raw);
    if (text.empty())
    {
        return fallback;
    }
    const bool digits = std::all_of(
        text.begin(), text.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; });
    // 18 digits always fit in 64 bits.
    if (!digits || text.size() > 18)
    {
        throw std::invalid_argument(
            "[" + section + "] " + key + " = '" + text +
            "': must be a whole number in [0, 999999999999999999]");
    }
    return static_cast<std::size_t>(std::stoull(text));
}

}  // namespace emslam::hwdrivers
