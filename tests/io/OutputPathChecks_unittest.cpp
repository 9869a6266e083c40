// SPDX-License-Identifier: BSD-3-Clause
// Outputs never replace a device, FIFO or folder, follow symbolic links to
// their targets, and an unwritable folder is found before any work.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/AtomicTextFile.h>
#include <emslam/io/OutputPathChecks.h>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace io = emslam::io;
namespace fs = std::filesystem;
using emslam::io::requireOutputFile;
using emslam::io::requireOutputFolder;
using emslam::test::expectThrowContaining;

namespace
{
std::string readText(const std::string& file)
{
    std::ifstream f(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

/** A folder no file can be created in: a read-only one for a normal user;
 * root writes anywhere, except into /proc. Empty if there is none. */
std::string unwritableFolder(const std::string& dir)
{
    if (::geteuid() != 0)
    {
        fs::create_directory(dir + "/ro");
        fs::permissions(dir + "/ro", fs::perms::owner_read | fs::perms::owner_exec);
        return dir + "/ro";
    }
    return fs::is_directory("/proc/self") ? "/proc" : "";
}
}  // namespace

TEST(OutputPathChecks, refusesDevicesFifosAndFoldersAndLeavesThemAlone)
{
    const std::string dir = emslam::test::makeTempDir("output_special");
    const std::string fifo = dir + "/pipe.rawlog";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expectThrowContaining(
        [&] { io::requireOutputFile(fifo, "output rawlog"); },
        {"output rawlog '" + fifo + "' exists and is a FIFO", "not a regular file"});
    expectThrowContaining(
        [&] { emslam::io::writeTextAtomically(fifo, "x"); }, {"pipe.rawlog", "FIFO"});
    EXPECT_TRUE(fs::is_fifo(fifo));
    EXPECT_FALSE(fs::exists(fifo + ".partial"));
    // Only looked at, never written: the type check comes first.
    expectThrowContaining(
        [&] { io::requireOutputFile("/dev/null", "output rawlog"); },
        {"'/dev/null' exists and is a character device"});
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    expectThrowContaining(
        [&] { io::requireOutputFile(dir, "ground-truth output file"); },
        {"ground-truth output file '" + dir + "' exists and is a folder"});
    // A link to a FIFO is refused too.
    fs::create_symlink(fifo, dir + "/link.rawlog");
    expectThrowContaining([&] { io::requireOutputFile(dir + "/link.rawlog", "output"); }, {"FIFO"});
}

TEST(OutputPathChecks, aSymbolicLinkIsFollowedAndKept)
{
    const std::string dir = emslam::test::makeTempDir("output_link");
    fs::create_directory(dir + "/runs");
    emslam::test::writeFile(dir + "/runs/real.txt", "old");
    fs::create_symlink("runs/real.txt", dir + "/latest.txt");  // relative target
    fs::create_symlink("latest.txt", dir + "/chain.txt");      // link to a link
    EXPECT_EQ(io::requireOutputFile(dir + "/chain.txt", "output"), dir + "/runs/real.txt");
    emslam::io::writeTextAtomically(dir + "/chain.txt", "new");
    EXPECT_TRUE(fs::is_symlink(dir + "/chain.txt"));
    EXPECT_TRUE(fs::is_symlink(dir + "/latest.txt"));
    EXPECT_EQ(readText(dir + "/runs/real.txt"), "new");
    // A dangling link: its target is created.
    fs::create_symlink("runs/new.txt", dir + "/dangling.txt");
    emslam::io::writeTextAtomically(dir + "/dangling.txt", "made");
    EXPECT_TRUE(fs::is_symlink(dir + "/dangling.txt"));
    EXPECT_EQ(readText(dir + "/runs/new.txt"), "made");
    // A loop of links.
    fs::create_symlink("b.txt", dir + "/a.txt");
    fs::create_symlink("a.txt", dir + "/b.txt");
    expectThrowContaining(
        [&] { io::requireOutputFile(dir + "/a.txt", "output"); },
        {"a.txt", "loop of symbolic links"});
}

TEST(OutputPathChecks, missingOrUnwritableFoldersFailBeforeAnyWork)
{
    const std::string dir = emslam::test::makeTempDir("output_folders");
    expectThrowContaining(
        [&] { io::requireOutputFile(dir + "/no/x.rawlog", "output rawlog"); },
        {"Folder '" + dir + "/no' of the output rawlog", "does not exist"});
    emslam::test::writeFile(dir + "/file", "x");
    expectThrowContaining(
        [&] { io::requireOutputFolder(dir + "/file/sub", "output folder"); },
        {"output folder '" + dir + "/file/sub'", "'" + dir + "/file' is a regular file"});
    EXPECT_NO_THROW(io::requireOutputFolder(dir + "/new/deeper", "output folder"));
    EXPECT_FALSE(fs::exists(dir + "/new"));  // checked, not created
    for (const auto& e : fs::directory_iterator(dir))
    {
        EXPECT_EQ(e.path().filename().string().find("probe"), std::string::npos) << e.path();
    }
    const std::string ro = unwritableFolder(dir);
    if (ro.empty())
    {
        GTEST_SKIP() << "no unwritable folder to try";
    }
    expectThrowContaining(
        [&] { io::requireOutputFolder(ro, "output folder"); }, {"cannot write into folder '" + ro});
    expectThrowContaining(
        [&] { io::requireOutputFile(ro + "/x.rawlog", "output rawlog"); },
        {"cannot write into folder '" + ro});
}
