// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

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

std::string makeTempDir(const std::string& tag)
{
    const fs::path p =
        fs::temp_directory_path() / ("emslam_test_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p.string();
}

}  // namespace emslam::test
