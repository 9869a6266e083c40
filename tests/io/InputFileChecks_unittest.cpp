// SPDX-License-Identifier: BSD-3-Clause
// Inputs that are no regular file, or far too big, fail with one clear line.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/InputFileChecks.h>

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace io = emslam::io;
namespace fs = std::filesystem;
using emslam::io::requireInputFile;
using emslam::test::expectThrowContaining;

TEST(InputFileChecks, acceptsARegularFileAndALinkToOne)
{
    const std::string dir = emslam::test::makeTempDir("input_ok");
    emslam::test::writeFile(dir + "/a.ini", "[A]\nx = 1\n");
    fs::create_symlink(dir + "/a.ini", dir + "/link.ini");
    EXPECT_NO_THROW(io::requireInputFile(dir + "/a.ini", "config file", 100));
    EXPECT_NO_THROW(io::requireInputFile(dir + "/link.ini", "config file", 100));
}

TEST(InputFileChecks, refusesMissingFoldersDevicesFifosAndHugeFiles)
{
    const std::string dir = emslam::test::makeTempDir("input_bad");
    expectThrowContaining(
        [&] { io::requireInputFile(dir + "/none.rawlog", "rawlog"); },
        {"rawlog '", "none.rawlog' does not exist"});
    expectThrowContaining(
        [&] { io::requireInputFile(dir, "rawlog"); }, {"rawlog '" + dir + "'", "is a folder"});
    ASSERT_EQ(::mkfifo((dir + "/pipe").c_str(), 0600), 0);
    expectThrowContaining(
        [&] { io::requireInputFile(dir + "/pipe", "config file"); },
        {"pipe' is not a regular file", "FIFO"});
    expectThrowContaining(
        [&] { io::requireInputFile("/dev/zero", "config file", emslam::io::MAX_INI_BYTES); },
        {"'/dev/zero'", "character device"});
    // A sparse 17 MiB file: no disk space used.
    {
        std::ofstream(dir + "/big.ini");
    }
    fs::resize_file(dir + "/big.ini", std::uintmax_t{17} << 20);
    expectThrowContaining(
        [&] { io::requireInputFile(dir + "/big.ini", "config file", emslam::io::MAX_INI_BYTES); },
        {"big.ini' is 17.0 MiB", "at most 16.0 MiB"});
}
