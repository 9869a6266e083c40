// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

namespace emslam::fuzz
{
/** A private folder for the files a harness hands to the readers (they take
 * file names, not text): one per process, so parallel fuzzers do not share
 * it, removed at exit. */
class FuzzFolder
{
public:
    FuzzFolder()
        : m_dir(
              std::filesystem::temp_directory_path() /
              ("emslam_fuzz_" + std::to_string(::getpid())))
    {
        std::filesystem::create_directories(m_dir);
    }
    ~FuzzFolder()
    {
        std::error_code ec;
        std::filesystem::remove_all(m_dir, ec);
    }
    FuzzFolder(const FuzzFolder&) = delete;
    FuzzFolder& operator=(const FuzzFolder&) = delete;

    /** Writes `bytes` to `name` (creating its parent folders) and returns its path. */
    std::string write(const std::string& name, std::string_view bytes) const
    {
        const auto path = m_dir / name;
        std::filesystem::create_directories(path.parent_path());
        std::ofstream(path, std::ios::binary | std::ios::trunc)
            .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        return path.string();
    }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    /** The one folder of this process. */
    static const FuzzFolder& instance()
    {
        static const FuzzFolder folder;
        return folder;
    }

private:
    std::filesystem::path m_dir;
};

/** The input as text. */
inline std::string_view asText(const std::uint8_t* data, std::size_t size)
{
    return {reinterpret_cast<const char*>(data), size};
}

/** Splits `text` at the first line that is exactly `separator`: the part
 * before it (with its line end) and the part after (empty if absent). Lets
 * one input hold two files. */
inline std::pair<std::string_view, std::string_view> splitAtLine(
    std::string_view text, std::string_view separator)
{
    std::size_t start = 0;
    while (start <= text.size())
    {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        if (text.substr(start, end - start) == separator)
        {
            const std::size_t after = std::min(end + 1, text.size());
            return {text.substr(0, start), text.substr(after)};
        }
        start = end + 1;
    }
    return {text, {}};
}
}  // namespace emslam::fuzz
