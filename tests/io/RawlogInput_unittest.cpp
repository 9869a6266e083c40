// SPDX-License-Identifier: BSD-3-Clause
// io::RawlogInput's progress: the fraction of the uncompressed stream, so the
// frame total extrapolated after the first frame is the real one.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/RawlogInput.h>
#include <emslam/io/RawlogOutput.h>

#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace io = emslam::io;
using emslam::io::RawlogInput;

namespace
{
constexpr std::size_t FRAMES = 120;

/** A stereo observation with smooth (well compressible) 160x120 images. */
mrpt::obs::CObservationStereoImages frame(std::size_t i)
{
    mrpt::obs::CObservationStereoImages o;
    o.timestamp = mrpt::Clock::fromDouble(1.7e9 + 0.1 * static_cast<double>(i));
    o.sensorLabel = "STEREO";
    for (auto* im : {&o.imageLeft, &o.imageRight})
    {
        im->resize(160, 120, mrpt::img::CH_GRAY);
        for (int y = 0; y < 120; y++)
        {
            for (int x = 0; x < 160; x++)
            {
                *im->ptr<std::uint8_t>(x, y) = static_cast<std::uint8_t>((x + y + i) & 0xff);
            }
        }
    }
    return o;
}

/** Reads one record and returns the frame total its fraction read implies
 * (what a progress line extrapolates: frames read / fraction read). */
std::size_t totalAfterFirstFrame(const std::string& file)
{
    io::RawlogInput in(file);
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    EXPECT_TRUE(in.next(batch));
    EXPECT_EQ(batch.size(), 1U);
    const double first_fraction = in.fractionRead();
    // And the last frame brings the fraction to 1.
    std::size_t n = 1;
    while (in.next(batch))
    {
        n += batch.size();
    }
    EXPECT_EQ(n, FRAMES);
    EXPECT_DOUBLE_EQ(in.fractionRead(), 1.0);
    EXPECT_EQ(in.bytesRead(), in.totalBytes());
    return static_cast<std::size_t>(std::lround(1.0 / first_fraction));
}
}  // namespace

TEST(RawlogInput, gzRawlogTotalAfterTheFirstFrameIsTheFrameCount)
{
    const std::string dir = emslam::test::makeTempDir("rawlog_input_gz");
    const std::string file = dir + "/frames.rawlog";
    {
        emslam::io::RawlogOutput out(file, 6);
        for (std::size_t i = 0; i < FRAMES; i++)
        {
            out.archive() << frame(i);
        }
        out.commit();
    }
    // Compressed well below the stream: dividing by the file size was wrong.
    const auto compressed = std::filesystem::file_size(file);
    io::RawlogInput in(file);
    EXPECT_GT(in.totalBytes(), 10 * compressed);
    const std::size_t total = totalAfterFirstFrame(file);
    EXPECT_NEAR(static_cast<double>(total), static_cast<double>(FRAMES), 0.01 * FRAMES);
}

TEST(RawlogInput, plainRawlogTotalAfterTheFirstFrameIsTheFrameCount)
{
    const std::string dir = emslam::test::makeTempDir("rawlog_input_plain");
    const std::string file = dir + "/frames.rawlog";
    {
        mrpt::io::CFileOutputStream f(file);
        auto a = mrpt::serialization::archiveFrom(f);
        for (std::size_t i = 0; i < FRAMES; i++)
        {
            a << frame(i);
        }
    }
    io::RawlogInput in(file);
    EXPECT_EQ(in.totalBytes(), std::filesystem::file_size(file));
    const std::size_t total = totalAfterFirstFrame(file);
    EXPECT_NEAR(static_cast<double>(total), static_cast<double>(FRAMES), 0.01 * FRAMES);
}

TEST(RawlogInput, uncompressedSizeFromTheGzipTrailer)
{
    constexpr std::uint64_t GIB = std::uint64_t{1} << 30;
    // Below 4 GiB the trailer is the size.
    EXPECT_EQ(io::RawlogInput::estimateUncompressedSize(5000, 1200, 0), 5000U);
    // Incompressible data: the stream is barely smaller than the file.
    EXPECT_EQ(io::RawlogInput::estimateUncompressedSize(99990, 100000, 0), 99990U);
    // 9 GiB compressed to 6 GiB: the trailer says 1 GiB (9 mod 4).
    EXPECT_EQ(io::RawlogInput::estimateUncompressedSize(GIB, 6 * GIB, 0), 9 * GIB);
    // 5 GiB compressed to 1 GiB: first taken as 1 GiB, then 5 GiB once read past it.
    EXPECT_EQ(io::RawlogInput::estimateUncompressedSize(GIB, GIB - 100, 0), GIB);
    EXPECT_EQ(io::RawlogInput::estimateUncompressedSize(GIB, GIB - 100, GIB + 1), 5 * GIB);
}

namespace
{
/** A gz rawlog of FRAMES frames; returns its bytes. */
std::string gzRawlogBytes(const std::string& file)
{
    {
        emslam::io::RawlogOutput out(file, 6);
        for (std::size_t i = 0; i < FRAMES; i++)
        {
            out.archive() << frame(i);
        }
        out.commit();
    }
    std::ifstream f(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

std::size_t readAll(io::RawlogInput& in)
{
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    std::size_t n = 0;
    while (in.next(batch))
    {
        n += batch.size();
    }
    return n;
}
}  // namespace

// A flipped byte in a gz rawlog is a corrupt file (zlib's CRC or deflate
// error, named), not a file that ends early for lack of data.
TEST(RawlogInput, flippedByteInAGzRawlogIsReportedAsCorrupt)
{
    const std::string dir = emslam::test::makeTempDir("rawlog_input_flip");
    std::string bytes = gzRawlogBytes(dir + "/good.rawlog");
    for (const double where : {0.3, 0.6, 0.9})
    {
        std::string damaged = bytes;
        damaged[static_cast<std::size_t>(where * static_cast<double>(damaged.size()))] ^= 0x10;
        const std::string file = dir + "/flipped.rawlog";
        std::ofstream(file, std::ios::binary)
            .write(damaged.data(), static_cast<long>(damaged.size()));
        io::RawlogInput in(file);
        EXPECT_LT(readAll(in), FRAMES) << where;
        EXPECT_TRUE(in.endedEarly()) << where;
        EXPECT_TRUE(in.corrupt()) << where << ": " << in.endReason();
        EXPECT_NE(in.endReason().find("the gz data is corrupt (zlib: "), std::string::npos)
            << in.endReason();
    }
    // The intact file reads to its end with no complaint.
    io::RawlogInput good(dir + "/good.rawlog");
    EXPECT_EQ(readAll(good), FRAMES);
    EXPECT_FALSE(good.endedEarly());
    EXPECT_FALSE(good.corrupt());
}

// A gz rawlog cut short is not corrupt: what was read is intact.
TEST(RawlogInput, cutGzRawlogEndsEarlyWithoutBeingCorrupt)
{
    const std::string dir = emslam::test::makeTempDir("rawlog_input_gzcut");
    const std::string bytes = gzRawlogBytes(dir + "/good.rawlog");
    const std::string file = dir + "/cut.rawlog";
    std::ofstream(file, std::ios::binary).write(bytes.data(), static_cast<long>(bytes.size() / 2));
    io::RawlogInput in(file);
    const std::size_t n = readAll(in);
    EXPECT_GT(n, 0U);
    EXPECT_LT(n, FRAMES);
    EXPECT_TRUE(in.endedEarly());
    EXPECT_FALSE(in.corrupt()) << in.endReason();
    EXPECT_NE(in.endReason().find("the file ends in the middle of the record"), std::string::npos)
        << in.endReason();
}
