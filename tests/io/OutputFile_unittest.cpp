// SPDX-License-Identifier: BSD-3-Clause
// A full disk, for real: Linux's /dev/full fails every write with ENOSPC.
// Each write error names the file and the OS reason.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/OutputFile.h>

#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using emslam::io::OutputFile;
using emslam::test::expectThrowContaining;

TEST(OutputFile, fullDiskOnCloseNamesTheFileAndTheReason)
{
    // A few bytes stay in the buffer: the error comes at close().
    OutputFile f("/dev/full", "stats.csv");
    f.text() << "frame,ms\n1,2\n";
    EXPECT_TRUE(f.text().good());
    expectThrowContaining(
        [&] { f.close(); }, {"cannot write 'stats.csv': No space left on device"});
}

TEST(OutputFile, fullDiskOnALargeWriteThrowsAtOnce)
{
    OutputFile f("/dev/full", "entropy_map.bin");
    const std::vector<char> block(1 << 20, 'x');
    expectThrowContaining(
        [&] { mrpt::serialization::archiveFrom(f).WriteBuffer(block.data(), block.size()); },
        {"cannot write 'entropy_map.bin': No space left on device"});
    // Text after the failure only sets the stream's badbit; close() says why.
    f.text() << "more";
    EXPECT_TRUE(f.text().bad());
    expectThrowContaining(
        [&] { f.close(); }, {"cannot write 'entropy_map.bin': No space left on device"});
}

TEST(OutputFile, writesAndNamesAFileThatCannotBeCreated)
{
    const std::string dir = emslam::test::makeTempDir("output_file");
    {
        OutputFile f(dir + "/a.txt");
        f.text() << "abc " << 12 << '\n';
        const char bytes[2] = {'x', 'y'};
        f.put(bytes, 2);
        EXPECT_EQ(f.getPosition(), 9u);
        f.close();
    }
    std::ifstream in(dir + "/a.txt", std::ios::binary);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "abc 12\nxy");
    expectThrowContaining(
        [&] { OutputFile(dir + "/no/such/folder.txt", "out.txt"); },
        {"cannot write 'out.txt': No such file or directory"});
}
