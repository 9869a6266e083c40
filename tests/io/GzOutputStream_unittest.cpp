// SPDX-License-Identifier: BSD-3-Clause
// gzip outputs (rawlogs, 3D scenes) on a full disk (/dev/full): the error
// names the file and the reason, also when only gzclose() fails (MRPT's
// CFileGZOutputStream ignores that one and a small file is lost silently).
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/GzOutputStream.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

using emslam::io::GzOutputStream;
using emslam::test::expectThrowContaining;

TEST(GzOutputStream, fullDiskAtCloseNamesTheFileAndTheReason)
{
    GzOutputStream f("/dev/full", 1, "map.3Dscene");
    auto a = mrpt::serialization::archiveFrom(f);
    a << std::uint32_t{42};
    expectThrowContaining(
        [&] { f.close(); }, {"cannot write 'map.3Dscene': No space left on device"});
}

TEST(GzOutputStream, fullDiskDuringWritesNamesTheFileAndTheReason)
{
    GzOutputStream f("/dev/full", 0, "out.rawlog");
    std::vector<std::uint8_t> block(1 << 20);
    for (std::size_t i = 0; i < block.size(); ++i)
    {
        block[i] = static_cast<std::uint8_t>(i * 7919);
    }
    expectThrowContaining(
        [&] { mrpt::serialization::archiveFrom(f).WriteBuffer(block.data(), block.size()); },
        {"cannot write 'out.rawlog': No space left on device"});
}

TEST(GzOutputStream, writesWhatCFileGZInputStreamReads)
{
    const std::string file = emslam::test::makeTempDir("gz_output") + "/a.gz";
    {
        GzOutputStream f(file, 1);
        auto a = mrpt::serialization::archiveFrom(f);
        a << std::string("hello") << 3.5;
        EXPECT_GT(f.getPosition(), 0u);
        f.close();
    }
    mrpt::io::CFileGZInputStream in(file);
    std::string s;
    double d = 0;
    auto a = mrpt::serialization::archiveFrom(in);
    a >> s >> d;
    EXPECT_EQ(s, "hello");
    EXPECT_EQ(d, 3.5);
    expectThrowContaining(
        [&] { GzOutputStream(file + "/under/a/file", 1, "x.rawlog"); },
        {"cannot write 'x.rawlog': "});
}
