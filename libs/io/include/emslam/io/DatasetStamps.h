// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace emslam::io
{
// Checks of the timestamps of dataset image lists (EuRoC data.csv, TUM
// rgb.txt / depth.txt): plausible, and strictly increasing within a list.

/** Earliest plausible image timestamp [ns since 1970-01-01 UTC]: one tick of
 * MRPT's 100 ns clock. MRPT reads a time of 0 as "no timestamp", and smaller
 * stamps would round to it. \ingroup emslam_io_grp \sa MAX_STAMP_NS */
constexpr std::int64_t MIN_STAMP_NS = 100;

/** Latest plausible image timestamp [ns since 1970-01-01 UTC]: 2100-01-01
 * 00:00:00 UTC. A later stamp is garbled (INT64_MAX ns is the year 2262).
 * \ingroup emslam_io_grp \sa MIN_STAMP_NS */
constexpr std::int64_t MAX_STAMP_NS = 4'102'444'800'000'000'000;

/** Parses `token`, the timestamp of line `line_no` of the image list `file`
 * (EuRoC: whole nanoseconds since the UNIX epoch, optionally followed by a
 * fraction of zeros, `1403715274312143104.0000000000`). Throws
 * std::runtime_error "<file>:<line_no>: timestamp '<token>' <reason>" if it
 * is not an integer, has a non-zero fraction (which would be dropped: a
 * fraction of a nanosecond is a garbled stamp), or is outside
 * [MIN_STAMP_NS, MAX_STAMP_NS]. The token is quoted by quotedExcerpt().
 * \ingroup emslam_io_grp \sa IncreasingStamps */
std::int64_t parseImageStampNs(
    std::string_view token, const std::string& file, std::size_t line_no);

/** Checks `t`, the timestamp [s since the UNIX epoch] written `token` on line
 * `line_no` of the image list `file` (TUM RGB-D): finite and within
 * [MIN_STAMP_NS, MAX_STAMP_NS] (1e-7 s to 4102444800 s). Throws
 * std::runtime_error "<file>:<line_no>: timestamp '<token>' is not a plausible
 * time: ..." otherwise. \ingroup emslam_io_grp \sa IncreasingStamps */
void requirePlausibleStampSeconds(
    double t, std::string_view token, const std::string& file, std::size_t line_no);

/** The order check of one image list: add() each stamp in the order of the
 * file; each must be later than the one before. A repeated or earlier stamp
 * means a garbled list (pairing by stamp would then pair the wrong images,
 * and time would go backwards). `Stamp` is `std::int64_t` (ns) or `double`
 * (s). \ingroup emslam_io_grp */
template <typename Stamp>
class IncreasingStamps
{
public:
    /** `file` names the list in messages. */
    explicit IncreasingStamps(std::string file);

    /** Records `t`, written `token` on line `line_no`. Throws
     * std::runtime_error "<file>:<line_no>: timestamp '<token>' repeats the
     * previous one (line <n>): timestamps must increase strictly", or "... is
     * before the previous one '<previous token>' (line <n>): ...", if `t` is
     * not later than the previous stamp. */
    void add(Stamp t, std::string_view token, std::size_t line_no);

private:
    std::string m_file;
    std::optional<Stamp> m_last;
    std::string m_last_token;
    std::size_t m_last_line{0};
};

extern template class IncreasingStamps<std::int64_t>;
extern template class IncreasingStamps<double>;

}  // namespace emslam::io
