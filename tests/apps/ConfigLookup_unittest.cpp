// SPDX-License-Identifier: BSD-3-Clause
// apps::findConfigFile(): a config by path, or a shipped one by name (the test
// binary runs in the build tree, so the source tree's config/ is shipped).
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/ConfigLookup.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

using emslam::apps::findConfigFile;
using emslam::apps::shippedConfigDirs;
namespace fs = std::filesystem;

namespace
{
std::string shippedDir(const std::string& kind)
{
    return (fs::path(emslam::test::sourceDir()) / "config" / kind).lexically_normal();
}

std::string shipped(const std::string& kind, const std::string& file)
{
    return shippedDir(kind) + "/" + file;
}

/** Runs `fn` with the working folder `dir`, then goes back. */
template <class Fn>
void inFolder(const std::string& dir, Fn fn)
{
    const auto before = fs::current_path();
    fs::current_path(dir);
    try
    {
        fn();
    }
    catch (...)
    {
        fs::current_path(before);
        throw;
    }
    fs::current_path(before);
}
}  // namespace

TEST(ConfigLookup, shippedNamesAreFoundWithOrWithoutTheSuffix)
{
    EXPECT_EQ(findConfigFile("kitti", "mapper"), shipped("mapper", "kitti.ini"));
    EXPECT_EQ(findConfigFile("kitti.ini", "mapper"), shipped("mapper", "kitti.ini"));
    EXPECT_EQ(findConfigFile("euroc", "odometry"), shipped("odometry", "euroc.ini"));
    EXPECT_EQ(findConfigFile("hall_double_loop", "sim"), shipped("sim", "hall_double_loop.ini"));
    // The source tree's folder is searched from the build tree only.
    ASSERT_EQ(shippedConfigDirs("mapper").size(), 1U);
    EXPECT_EQ(shippedConfigDirs("mapper").front(), shippedDir("mapper"));
    EXPECT_TRUE(shippedConfigDirs("no-such-kind").empty());
}

TEST(ConfigLookup, pathsAndLocalFilesAreReturnedUnchanged)
{
    EXPECT_EQ(findConfigFile("", "mapper"), "");
    // A path, even a missing one: its own error names the file.
    EXPECT_EQ(findConfigFile("some/where/kitti.ini", "mapper"), "some/where/kitti.ini");
    EXPECT_EQ(findConfigFile("./kitti", "mapper"), "./kitti");
    // A file of the working folder wins over the shipped one of that name.
    const std::string dir = emslam::test::makeTempDir("config_lookup_local");
    emslam::test::writeFile(dir + "/kitti.ini", "[EntropySlam]\n");
    inFolder(
        dir,
        [&]
        {
            EXPECT_EQ(findConfigFile("kitti.ini", "mapper"), "kitti.ini");
            EXPECT_EQ(findConfigFile("kitti", "mapper"), shipped("mapper", "kitti.ini"));
        });
}

TEST(ConfigLookup, unknownNameListsTheShippedOnes)
{
    emslam::test::expectThrowContaining(
        [] { findConfigFile("kiti", "mapper"); },
        {"no mapper config 'kiti'", "3dof-low-structured, ", ", euroc, kitti, paper in ",
         shippedDir("mapper")});
    emslam::test::expectThrowContaining(
        [] { findConfigFile("kitti", "no-such-kind"); },
        {"no no-such-kind config 'kitti'", "no folder of shipped no-such-kind configs"});
}
