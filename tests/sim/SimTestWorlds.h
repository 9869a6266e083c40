// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <string>
#include <vector>

namespace emslam::test
{
/** The world INI files shipped in config/sim/ (full paths, sorted). */
std::vector<std::string> shippedSimWorlds();

/** A minimal valid world INI text: a short 3DOF path in a straight corridor.
 * `extra` is appended (later keys of a section override earlier ones only
 * if written in a new section block, so pass whole sections). */
std::string tinyWorldIni(const std::string& extra = "");
}  // namespace emslam::test
