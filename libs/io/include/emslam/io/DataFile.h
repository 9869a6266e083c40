// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <istream>
#include <string>

namespace emslam::io
{
/** Largest dataset text file read [bytes] (1 GiB): lists, calibrations and
 * trajectories of real sequences are a few MB at most.
 * \ingroup emslam_io_grp \sa openTextFile */
constexpr std::uintmax_t MAX_TEXT_FILE_BYTES = std::uintmax_t{1} << 30;

/** Longest line of a dataset text file [bytes]; real lines are under 300.
 * \ingroup emslam_io_grp \sa readBoundedLine */
constexpr std::size_t MAX_LINE_BYTES = std::size_t{1} << 16;

/** Opens the dataset text file `file` for reading. Throws std::runtime_error
 * "Cannot open <what> '<file>': <reason>" if it does not exist, is not a
 * regular file (a folder, a FIFO, a device such as /dev/zero, which would
 * never end), is larger than MAX_TEXT_FILE_BYTES or cannot be opened.
 * \ingroup emslam_io_grp \sa readBoundedLine */
std::ifstream openTextFile(const std::string& file, const std::string& what);

/** std::getline() with a length limit: reads the next line of `in` into
 * `line` (without its '\n') and returns true, or returns false at the end of
 * the input. Throws std::runtime_error "<file>:<line_no>: line longer than
 * MAX_LINE_BYTES bytes" instead of reading on (binary garbage, a file with no
 * line ends); `file` and `line_no` only name the place.
 * \ingroup emslam_io_grp \sa openTextFile */
bool readBoundedLine(
    std::istream& in, std::string& line, const std::string& file, std::size_t line_no);

}  // namespace emslam::io
