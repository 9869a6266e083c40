// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace emslam::io
{
/** A strict reader of the small YAML subset that EuRoC (ASL) `sensor.yaml`
 * files use, instead of a general YAML parser (OpenCV 4.6's hangs or
 * overflows its stack on some malformed files):
 * \code
 *   %YAML:1.0                        optional directive on the first line
 *   # comment                        comments, also after a value (" #...")
 *   sensor_type: camera              key: scalar (rest of the line)
 *   resolution: [752, 480]           key: flow list of scalars, one level only
 *   T_BS:                            key with no value: a map of the indented
 *     cols: 4                        lines below it, one level only; read as
 *     data: [1, 0, 0, 0,             "T_BS.cols", "T_BS.data"; a list may
 *            0, 1, 0, 0, ...]        span several lines
 * \endcode
 * Anything else (nested lists, deeper maps, tabs, duplicate keys, control
 * characters, files over MAX_FILE_BYTES) is refused. The reader is linear in
 * the file size and does not recurse. Every error names the file, the line and,
 * where known, the key.
 * \ingroup emslam_io_grp \sa loadEurocCalibration */
class EurocSensorYaml
{
public:
    /** Largest file accepted [bytes]; real sensor.yaml files are under 2 KiB. */
    static constexpr std::size_t MAX_FILE_BYTES = 1u << 20;

    /** Reads and parses `file`. Throws std::runtime_error naming the file if it
     * is not a regular file, is larger than MAX_FILE_BYTES, or does not parse. */
    static EurocSensorYaml load(const std::string& file);

    /** Parses `text`; `file` only names the source in error messages. */
    static EurocSensorYaml parse(std::string_view text, const std::string& file);

    /** Whether `key` is present ("T_BS" for the map, "T_BS.data" for its entries). */
    bool has(const std::string& key) const;
    /** Whether `key` is a map (a key line with no value, followed by indented keys). */
    bool isMap(const std::string& key) const;
    /** Whether `key` is a flow list `[...]`. */
    bool isList(const std::string& key) const;

    /** The scalar value of `key`, unquoted. Throws naming the key and its line if
     * it is missing, a list or a map. */
    std::string text(const std::string& key) const;

    /** The numbers of the list `key`; their count must be one of `allowed_sizes`.
     * Throws naming the key and its line if it is missing, not a list, holds an
     * element that is not a finite number, or has another count. */
    std::vector<double> numbers(
        const std::string& key, const std::vector<std::size_t>& allowed_sizes) const;

    /** The scalar `key` as a finite number. Throws like text(), and if it is not one. */
    double number(const std::string& key) const;

    /** Line where `key` starts (1-based). Throws if it is missing. */
    std::size_t lineOf(const std::string& key) const;

    /** The file name used in messages. */
    const std::string& fileName() const { return m_file; }

private:
    enum class Kind
    {
        Scalar,
        List,
        Map
    };
    struct Entry
    {
        Kind kind{Kind::Scalar};
        std::string scalar;
        std::vector<std::string> items;
        std::size_t line{0};
    };

    class Parser;

    const Entry& entry(const std::string& key) const;
    [[noreturn]] void fail(
        std::size_t line, const std::string& key, const std::string& problem) const;

    std::string m_file;
    std::map<std::string, Entry> m_entries;
};

}  // namespace emslam::io
