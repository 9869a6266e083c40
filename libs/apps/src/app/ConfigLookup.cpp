// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/ConfigLookup.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace emslam::apps
{
namespace
{
/** The running executable, or "" where /proc is not mounted. */
fs::path executablePath()
{
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : exe;
}

/** True if `path` lies inside `dir` (both absolute and normalized). */
bool isInside(const fs::path& path, const fs::path& dir)
{
    const auto rel = path.lexically_normal().lexically_relative(dir.lexically_normal());
    return !rel.empty() && *rel.begin() != "..";
}

bool isFile(const fs::path& p)
{
    std::error_code ec;
    return fs::is_regular_file(p, ec);
}

/** The `.ini` files of `dir` by stem, sorted: "kitti, euroc, ...". */
std::string shippedNames(const std::string& dir)
{
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
    {
        if (e.path().extension() == ".ini" && isFile(e.path()))
        {
            names.push_back(e.path().stem().string());
        }
    }
    std::sort(names.begin(), names.end());
    std::string out;
    for (const auto& n : names)
    {
        out += (out.empty() ? "" : ", ") + n;
    }
    return out;
}
}  // namespace

std::vector<std::string> shippedConfigDirs(const std::string& kind)
{
    std::vector<fs::path> candidates;
    const fs::path exe = executablePath();
    if (!exe.empty())
    {
        candidates.push_back(exe.parent_path() / EMSLAM_CONFIG_FROM_BINDIR / kind);
        if (isInside(exe, EMSLAM_BUILD_TREE))
        {
            candidates.push_back(fs::path(EMSLAM_SOURCE_TREE) / "config" / kind);
        }
    }
    std::vector<std::string> dirs;
    for (const auto& c : candidates)
    {
        std::error_code ec;
        if (fs::is_directory(c, ec))
        {
            dirs.push_back(c.lexically_normal().string());
        }
    }
    return dirs;
}

std::string findConfigFile(const std::string& name, const std::string& kind)
{
    if (name.empty() || name.find('/') != std::string::npos || isFile(name))
    {
        return name;
    }
    const std::string file_name = fs::path(name).extension() == ".ini" ? name : name + ".ini";
    const auto dirs = shippedConfigDirs(kind);
    for (const auto& dir : dirs)
    {
        const fs::path file = fs::path(dir) / file_name;
        if (isFile(file))
        {
            return file.string();
        }
    }
    std::string shipped;
    for (const auto& dir : dirs)
    {
        shipped += (shipped.empty() ? "" : "; ") + shippedNames(dir) + " in " + dir;
    }
    throw std::invalid_argument(
        "no " + kind + " config '" + name + "': not a file, nor a shipped name" +
        (shipped.empty() ? " (no folder of shipped " + kind + " configs found beside the program)"
                         : " (" + shipped + ")"));
}

}  // namespace emslam::apps
