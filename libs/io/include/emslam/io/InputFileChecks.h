// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>

namespace emslam::io
{
/** The largest INI file an app reads [bytes]: 16 MiB, far above any real
 * configuration, so that a wrong path (a device, a dataset) fails at once
 * instead of filling the memory. \ingroup emslam_io_grp */
constexpr std::uintmax_t MAX_INI_BYTES = std::uintmax_t{16} << 20;

/** Throws std::runtime_error, naming `what` and `file`, unless `file` is a
 * regular file (or a symbolic link to one) of at most `max_bytes`:
 * "WHAT 'FILE' does not exist", "... is a folder, not a file",
 * "... is not a regular file (it is a character device)",
 * "... is 40.0 MiB; a WHAT has at most 16.0 MiB". Every app checks its
 * inputs with it before any work, so a wrong path fails with one clear line.
 * \ingroup emslam_io_grp \sa requireOutputFile() */
void requireInputFile(
    const std::string& file,
    const std::string& what,
    std::uintmax_t max_bytes = std::numeric_limits<std::uintmax_t>::max());

/** "a folder", "a character device", "a FIFO", ...: what a file of type `t`
 * is, for error messages. \ingroup emslam_io_grp */
std::string fileTypeName(std::filesystem::file_type t);

}  // namespace emslam::io
