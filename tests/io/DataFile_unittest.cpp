// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/DataFile.h>
#include <emslam/io/KittiTrajectory.h>
#include <emslam/io/TumTrajectory.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

using emslam::io::MAX_LINE_BYTES;
using emslam::io::openTextFile;
using emslam::io::readBoundedLine;
using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

TEST(DataFile, readsLinesLikeGetline)
{
    std::istringstream in("a b\r\n\nlast");
    std::string line;
    ASSERT_TRUE(readBoundedLine(in, line, "f", 1));
    EXPECT_EQ(line, "a b\r");
    ASSERT_TRUE(readBoundedLine(in, line, "f", 2));
    EXPECT_EQ(line, "");
    ASSERT_TRUE(readBoundedLine(in, line, "f", 3));
    EXPECT_EQ(line, "last");
    EXPECT_FALSE(readBoundedLine(in, line, "f", 4));
    std::istringstream ends_with_newline("x\n");
    ASSERT_TRUE(readBoundedLine(ends_with_newline, line, "f", 1));
    EXPECT_FALSE(readBoundedLine(ends_with_newline, line, "f", 2));
}

TEST(DataFile, overlongLineIsAnErrorNamingFileAndLine)
{
    std::istringstream in("ok\n" + std::string(MAX_LINE_BYTES + 1, '7'));
    std::string line;
    ASSERT_TRUE(readBoundedLine(in, line, "times.txt", 1));
    expectThrowContaining(
        [&]() { readBoundedLine(in, line, "times.txt", 2); }, {"times.txt:2", "longer than"});
    std::istringstream exact(std::string(MAX_LINE_BYTES, '7'));
    ASSERT_TRUE(readBoundedLine(exact, line, "f", 1));
    EXPECT_EQ(line.size(), MAX_LINE_BYTES);
}

TEST(DataFile, refusesMissingFilesFoldersAndDevices)
{
    const std::string dir = emslam::test::makeTempDir("datafile");
    expectThrowContaining(
        [&]() { openTextFile(dir + "/none.txt", "trajectory file"); },
        {"trajectory file", dir + "/none.txt", "no such file"});
    expectThrowContaining(
        [&]() { openTextFile(dir, "trajectory file"); }, {dir, "not a regular file"});
    if (std::filesystem::exists("/dev/zero"))
    {
        expectThrowContaining(
            []() { openTextFile("/dev/zero", "trajectory file"); },
            {"/dev/zero", "not a regular file"});
    }
}

// The readers built on it: /dev/zero and binary garbage give an error, not an endless read.
TEST(DataFile, datasetReadersRefuseDevicesAndGarbage)
{
    if (std::filesystem::exists("/dev/zero"))
    {
        expectThrowContaining(
            []() { emslam::io::TumTrajectory::fromFile("/dev/zero"); },
            {"/dev/zero", "not a regular file"});
        expectThrowContaining(
            []() { emslam::io::KittiTrajectory::readTimes("/dev/zero"); },
            {"/dev/zero", "not a regular file"});
    }
    const std::string dir = emslam::test::makeTempDir("datafile_garbage");
    std::string garbage(3 * MAX_LINE_BYTES, '\0');
    for (std::size_t i = 0; i < garbage.size(); ++i)
    {
        garbage[i] = static_cast<char>((i * 131) % 256 == '\n' ? 0 : (i * 131) % 256);
    }
    writeFile(dir + "/garbage.tum", garbage);
    expectThrowContaining(
        [&]() { emslam::io::TumTrajectory::fromFile(dir + "/garbage.tum"); },
        {"garbage.tum:1", "longer than"});
    writeFile(dir + "/times.txt", "0.0\n" + std::string(MAX_LINE_BYTES + 5, '1') + "\n");
    expectThrowContaining(
        [&]() { emslam::io::KittiTrajectory::readTimes(dir + "/times.txt"); },
        {"times.txt:2", "longer than"});
    writeFile(dir + "/huge.tum", "1e400 0 0 0 0 0 0 1\n");
    expectThrowContaining(
        [&]() { emslam::io::TumTrajectory::fromFile(dir + "/huge.tum"); }, {"huge.tum:1"});
}
