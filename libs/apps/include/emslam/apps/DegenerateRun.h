// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace emslam::apps
{
/** Exit code of a run that wrote all its outputs but whose result is
 * degenerate (see degenerateRunWarning()): not 0, so scripts notice; not 1,
 * which means an error stopped the run. \ingroup emslam_apps_grp */
constexpr int EXIT_DEGENERATE = 3;

/** Why a finished run's result is nonsense, or "" when it is not: more than
 * half of its egomotion steps (frame pairs) failed, so most poses are copies
 * of the one before, or its map holds no point (`map_points`; nullopt for
 * apps without a map). E.g. "28 of 29 egomotion steps failed (97 %)".
 * \ingroup emslam_apps_grp */
std::string degenerateRunWarning(
    std::size_t steps, std::size_t failed_steps, std::optional<std::size_t> map_points);

}  // namespace emslam::apps
