// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/InputOutputClash.h>

#include <sys/stat.h>

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace emslam::io
{
namespace
{
/** Device and inode of what `path` names (links followed), if it exists. */
std::optional<std::pair<dev_t, ino_t>> fileIdentity(const std::string& path)
{
    struct stat st
    {
    };
    if (::stat(path.c_str(), &st) != 0)
    {
        return std::nullopt;
    }
    return std::make_pair(st.st_dev, st.st_ino);
}

/** The absolute path with every existing link resolved, or the lexically
 * normal absolute path if that fails. */
fs::path resolved(const std::string& path)
{
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    return ec ? fs::absolute(path).lexically_normal() : p;
}

[[noreturn]] void refuse(const RolePath& out, const std::string& relation, const RolePath& in)
{
    throw std::invalid_argument(
        out.what + " '" + out.path + "' " + relation + " " + in.what + " '" + in.path +
        "'; refusing to overwrite an input, give another output");
}
}  // namespace

void requireOutputsAreNotInputs(
    const std::vector<RolePath>& outputs, const std::vector<RolePath>& inputs)
{
    for (const auto& out : outputs)
    {
        if (out.path.empty())
        {
            continue;
        }
        const auto out_id = fileIdentity(out.path);
        const fs::path out_path = resolved(out.path);
        for (const auto& in : inputs)
        {
            if (in.path.empty())
            {
                continue;
            }
            const auto in_id = fileIdentity(in.path);
            const fs::path in_path = resolved(in.path);
            if ((out_id && in_id && *out_id == *in_id) || out_path == in_path)
            {
                refuse(out, "is", in);
            }
        }
    }
}

std::vector<RolePath> filesOfOutputFolder(
    const std::string& folder, const std::vector<std::string>& names, const std::string& what)
{
    std::vector<RolePath> files;
    for (const auto& n : names)
    {
        files.push_back({what, (fs::path(folder) / n).string()});
    }
    return files;
}

}  // namespace emslam::io
