// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace emslam::io
{
// Strict, locale-independent parsing of the lines and numbers of dataset text
// files (KITTI, EuRoC, TUM): a token is a number only if all of it is one.

/** `s` without its leading and trailing blanks (space, tab, CR, LF); empty if
 * `s` is all blanks. The result views the memory of `s`.
 * \ingroup emslam_io_grp \sa isBlank */
std::string_view trimmed(std::string_view s);

/** The comma-separated fields of `line`, each trimmed(); one empty field for
 * an empty line (the CSV files of EuRoC).
 * \ingroup emslam_io_grp \sa trimmed */
std::vector<std::string> splitCommaFields(std::string_view line);

/** True if `line` holds only blanks (space, tab, CR, LF), or nothing.
 * \ingroup emslam_io_grp \sa isCommentOrBlank, trimmed */
bool isBlank(std::string_view line);

/** True if `line` is blank (isBlank()) or its first non-blank character is
 * `#` (a comment line of the TUM and EuRoC text formats).
 * \ingroup emslam_io_grp \sa isBlank */
bool isCommentOrBlank(std::string_view line);

/** Reads `in` to its end, line by line (readBoundedLine(): a line over
 * MAX_LINE_BYTES throws, naming `source` and the line), and calls
 * `on_line(line, line_no)` for every line that is not isCommentOrBlank().
 * `line_no` counts every line of `in` from 1, skipped ones included, for
 * "file:line" messages; exceptions thrown by `on_line` propagate.
 * \ingroup emslam_io_grp \sa isCommentOrBlank, readBoundedLine */
void forEachDataLine(
    std::istream& in,
    const std::function<void(const std::string& line, std::size_t line_no)>& on_line,
    const std::string& source = "input");

/** As forEachDataLine(), but only blank lines are skipped: comment lines
 * reach `on_line` too (for formats whose comments carry a header, or that
 * have none). \ingroup emslam_io_grp */
void forEachNonBlankLine(
    std::istream& in,
    const std::function<void(const std::string& line, std::size_t line_no)>& on_line,
    const std::string& source = "input");

/** Parses the whole of `token` as a `double` (`std::from_chars` general
 * format: decimal or exponent notation, `inf`, `nan`), also accepting one
 * leading `+` (dropped before parsing, so `+-1` reads as -1). Returns false,
 * leaving `v` unchanged, if `token` is empty, is not a number, has trailing
 * characters (blanks included) or is out of the range of `double`.
 * Non-finite values (`inf`, `nan`) are accepted: check them with
 * `std::isfinite` where they are not allowed.
 * \ingroup emslam_io_grp \sa parseInt64, parseNumbers */
bool parseDouble(std::string_view token, double& v);

/** Parses the whole of `token` as a decimal `std::int64_t` (an optional `-`,
 * then digits; a leading `+` is *not* accepted). Returns false, leaving `v`
 * unchanged, if `token` is empty, is not an integer, has trailing characters
 * or does not fit in 64 bits.
 * \ingroup emslam_io_grp \sa parseDouble */
bool parseInt64(std::string_view token, std::int64_t& v);

/** Parses a nanosecond timestamp as EuRoC writes them: a non-negative decimal
 * integer that fits in `std::int64_t` (0 to 9223372036854775807, about year
 * 2262), optionally followed by `.` and zeros, which are dropped
 * (`1403715274312143104.0000000000`). Returns false, leaving `v` unchanged,
 * otherwise (negative, too large, not an integer, a non-zero fraction such as
 * `.5`, which would otherwise be lost). Non-negative stamps can be subtracted
 * from each other without overflow. Image lists check more
 * (parseImageStampNs()).
 * \ingroup emslam_io_grp \sa parseInt64 */
bool parseNanoseconds(std::string_view token, std::int64_t& v);

/** Splits `line` into tokens at any run of the characters of `separators`
 * (leading and trailing separators ignored) and parses every token with
 * parseDouble(). `out` is cleared first and receives the numbers in order;
 * an empty line, or one of separators only, gives an empty `out` and true.
 * Returns false at the first token that is not a number (`out` then holds
 * the numbers before it). The default separators are space, tab and CR (the
 * CR of CRLF files); pass `" \t,\r"` to also accept commas.
 * \ingroup emslam_io_grp \sa parseDouble */
bool parseNumbers(
    std::string_view line, std::vector<double>& out, std::string_view separators = " \t\r");

/** Longest piece of input an error message quotes [bytes].
 * \ingroup emslam_io_grp \sa quotedExcerpt */
constexpr std::size_t MAX_QUOTED_BYTES = 60;

/** `text` as the error messages of the readers quote input: between single
 * quotes; if longer than MAX_QUOTED_BYTES, only its first MAX_QUOTED_BYTES
 * bytes (fewer rather than cut a UTF-8 character), then "…" and its length:
 * `'abc…' (100000 bytes)`. The bytes are not otherwise changed. A message
 * then stays short whatever the line (a 400 KB line is echoed as 60 bytes).
 * \ingroup emslam_io_grp */
std::string quotedExcerpt(std::string_view text);

}  // namespace emslam::io
