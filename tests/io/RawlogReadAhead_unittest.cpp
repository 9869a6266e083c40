// SPDX-License-Identifier: BSD-3-Clause
// io::RawlogReadAhead hands out what io::RawlogInput reads, in order, and reports the
// input's state as of the entries handed out, not of the one read ahead.
#include "TestData.h"

#include <emslam/io/RawlogInput.h>
#include <emslam/io/RawlogOutput.h>
#include <emslam/io/RawlogReadAhead.h>

#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace io = emslam::io;
using emslam::io::RawlogInput;
using emslam::io::RawlogReadAhead;

namespace
{
constexpr std::size_t FRAMES = 40;

/** A gz rawlog of FRAMES stereo observations stamped 1, 2, ...; returns its bytes. */
std::string writeRawlog(const std::string& file)
{
    {
        emslam::io::RawlogOutput out(file, 6);
        for (std::size_t i = 0; i < FRAMES; ++i)
        {
            mrpt::obs::CObservationStereoImages o;
            o.timestamp = mrpt::Clock::fromDouble(1.0 + static_cast<double>(i));
            o.imageLeft.resize(64, 48, mrpt::img::CH_GRAY);
            o.imageRight.resize(64, 48, mrpt::img::CH_GRAY);
            for (int y = 0; y < 48; ++y)
            {
                for (int x = 0; x < 64; ++x)
                {
                    *o.imageLeft.ptr<std::uint8_t>(x, y) =
                        static_cast<std::uint8_t>((x * 7 + y * 13 + i * 31) & 0xff);
                }
            }
            out.archive() << o;
        }
        out.commit();
    }
    std::ifstream f(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}
}  // namespace

TEST(RawlogReadAhead, handsOutEveryRecordInOrder)
{
    const std::string dir = emslam::test::makeTempDir("read_ahead_order");
    writeRawlog(dir + "/frames.rawlog");
    io::RawlogInput in(dir + "/frames.rawlog");
    io::RawlogReadAhead reader(in);
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    std::size_t n = 0;
    double last_fraction = 0;
    while (reader.next(batch))
    {
        ASSERT_EQ(batch.size(), 1U);
        EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(batch[0]->timestamp), 1.0 + static_cast<double>(n));
        ++n;
        EXPECT_EQ(reader.recordsRead(), n);
        EXPECT_GE(reader.fractionRead(), last_fraction);
        last_fraction = reader.fractionRead();
    }
    EXPECT_EQ(n, FRAMES);
    EXPECT_TRUE(batch.empty());
    EXPECT_DOUBLE_EQ(reader.fractionRead(), 1.0);
    EXPECT_FALSE(reader.endedEarly());
    EXPECT_FALSE(reader.next(batch));  // and stays at the end
}

// A damaged record after the last one the caller takes is read ahead, but
// not reported; reading on reaches it and reports it.
TEST(RawlogReadAhead, aDamagedRecordNotAskedForIsNotReported)
{
    const std::string dir = emslam::test::makeTempDir("read_ahead_cut");
    const std::string bytes = writeRawlog(dir + "/good.rawlog");
    const std::string file = dir + "/cut.rawlog";
    std::ofstream(file, std::ios::binary).write(bytes.data(), static_cast<long>(bytes.size() / 2));
    std::size_t readable = 0;
    {
        io::RawlogInput in(file);
        std::vector<mrpt::obs::CObservation::Ptr> batch;
        while (in.next(batch))
        {
            ++readable;
        }
        ASSERT_TRUE(in.endedEarly());
        ASSERT_GT(readable, 2U);
    }
    {
        // Stop at the last readable record: the cut after it was read ahead.
        io::RawlogInput in(file);
        io::RawlogReadAhead reader(in);
        std::vector<mrpt::obs::CObservation::Ptr> batch;
        for (std::size_t i = 0; i < readable; ++i)
        {
            ASSERT_TRUE(reader.next(batch));
        }
        EXPECT_FALSE(reader.endedEarly());
        EXPECT_TRUE(reader.endReason().empty());
        // One more: the cut, as io::RawlogInput reports it.
        EXPECT_FALSE(reader.next(batch));
        EXPECT_TRUE(reader.endedEarly());
        EXPECT_FALSE(reader.corrupt());
        EXPECT_EQ(reader.recordsRead(), readable);
        EXPECT_NE(reader.endReason().find("record " + std::to_string(readable)), std::string::npos)
            << reader.endReason();
    }
}
