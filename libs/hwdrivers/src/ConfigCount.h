// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <cstddef>
#include <string>

namespace emslam::hwdrivers
{
/** Reads a frame index or count: a whole number >= 0 (absent: `fallback`).
 * MRPT's read_uint64_t would wrap "-1" to 2^64 - 1 silently; this throws
 * std::invalid_argument naming the section, the key and the value. */
std::size_t readCount(
    const mrpt::config::CConfigFileBase& c,
    const std::string& section,
    const std::string& key,
    std::size_t fallback);

}  // namespace emslam::hwdrivers
