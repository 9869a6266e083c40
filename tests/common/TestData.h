// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <string>

namespace emslam::test
{
/** Folder with the real test data (KITTI / EuRoC excerpts). The environment
 * variable EMSLAM_TEST_DATA overrides the CMake setting of the same name.
 * Returns "" when the folder does not exist. */
std::string testDataDir();

/** `testDataDir() + "/" + rel` if that exists, else "". */
std::string testDataPath(const std::string& rel);

/** The project source folder (for config/ and share/ files). */
std::string sourceDir();

/** A fresh, empty temporary folder, unique to this process and `tag`;
 * removed by removeTempDirs() when the process's tests have passed. */
std::string makeTempDir(const std::string& tag);

/** Removes the folders makeTempDir() made (test_main calls it after the
 * tests, unless one failed or EMSLAM_KEEP_TEST_DIRS is set: then they stay
 * for a look). Returns how many it removed. */
std::size_t removeTempDirs();

}  // namespace emslam::test

/** Skips the current test, with a message, when the relative path is absent
 * from the test data folder; otherwise declares `var` holding its full path. */
#define EMSLAM_REQUIRE_TEST_DATA(var, rel)                                              \
    const std::string var = ::emslam::test::testDataPath(rel);                          \
    if (var.empty())                                                                    \
    {                                                                                   \
        GTEST_SKIP() << "test data '" << (rel) << "' not found (set EMSLAM_TEST_DATA)"; \
    }
