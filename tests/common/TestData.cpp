// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

namespace fs = std::filesystem;

namespace emslam::test
{
std::string testDataDir()
{
    const char* env = std::getenv("EMSLAM_TEST_DATA");
    const std::string dir = (env != nullptr && *env != '\0') ? env : EMSLAM_TEST_DATA_DEFAULT;
    std::error_code ec;
    return fs::is_directory(dir, ec) ? dir : std::string();
}

std::string testDataPath(const std::string& rel)
{
    const std::string dir = testDataDir();
    if (dir.empty())
    {
        return {};
    }
    const std::string p = dir + "/" + rel;
    std::error_code ec;
    return fs::exists(p, ec) ? p : std::string();
}

std::string sourceDir()
{
    return EMSLAM_SOURCE_DIR;
}

namespace
{
std::vector<std::string>& tempDirs()
{
    static std::vector<std::string> dirs;
    return dirs;
}
}  // namespace

std::string makeTempDir(const std::string& tag)
{
    const fs::path p =
        fs::temp_directory_path() / ("emslam_test_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    if (std::find(tempDirs().begin(), tempDirs().end(), p.string()) == tempDirs().end())
    {
        tempDirs().push_back(p.string());
    }
    return p.string();
}

std::size_t removeTempDirs()
{
    std::size_t removed = 0;
    for (const auto& d : tempDirs())
    {
        std::error_code ec;
        // A test may have left a folder read-only (the output-failure tests).
        fs::permissions(d, fs::perms::owner_all, fs::perm_options::add, ec);
        for (auto it = fs::recursive_directory_iterator(d, ec);
             !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
        {
            std::error_code ignored;
            fs::permissions(it->path(), fs::perms::owner_all, fs::perm_options::add, ignored);
        }
        ec.clear();
        removed += fs::remove_all(d, ec) > 0 && !ec;
    }
    tempDirs().clear();
    return removed;
}

}  // namespace emslam::test
