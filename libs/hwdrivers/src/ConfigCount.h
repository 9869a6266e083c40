// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <string>

namespace emslam::hwdrivers
{
/** Parses a frame index or count: a whole number >= 0 (blank: `fallback`).
 * MRPT's read_uint64_t would wrap "-1" to 2^64 - 1 silently; this throws
 * std::invalid_argument naming the section, the key and the value. */
std::size_t parseCount(
    const std::string& text,
    const std::string& section,
    const std::string& key,
    std::size_t fallback);

}  // namespace emslam::hwdrivers
