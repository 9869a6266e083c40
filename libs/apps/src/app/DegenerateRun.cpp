// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/DegenerateRun.h>

namespace emslam::apps
{
std::string degenerateRunWarning(
    std::size_t steps, std::size_t failed_steps, std::optional<std::size_t> map_points)
{
    std::string why;
    if (steps > 0 && 2 * failed_steps > steps)
    {
        why = std::to_string(failed_steps) + " of " + std::to_string(steps) +
              " egomotion steps failed (" + std::to_string(100 * failed_steps / steps) + " %)";
    }
    if (map_points && *map_points == 0)
    {
        why += (why.empty() ? "" : "; ") + std::string("the map has no point");
    }
    return why;
}

}  // namespace emslam::apps
