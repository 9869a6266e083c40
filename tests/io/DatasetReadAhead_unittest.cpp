// SPDX-License-Identifier: BSD-3-Clause
// io::DatasetReadAhead hands out a dataset's frames in order, one per entry,
// and ends early, naming the frame and file, at an image it cannot read.
#include "SyntheticKitti.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/DatasetReadAhead.h>
#include <emslam/io/KittiSequence.h>

#include <mrpt/core/Clock.h>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using emslam::io::DatasetReadAhead;
using emslam::io::KittiSequence;

TEST(DatasetReadAhead, handsOutEveryFrameInOrder)
{
    const std::string root = emslam::test::makeTempDir("dataset_read_ahead");
    const KittiSequence seq(emslam::test::writeKittiSequence(root, 4));
    DatasetReadAhead reader(seq);
    EXPECT_EQ(reader.recordsRead(), 0U);
    EXPECT_DOUBLE_EQ(reader.fractionRead(), 0.0);
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    for (std::size_t i = 0; i < 4; ++i)
    {
        ASSERT_TRUE(reader.next(batch)) << i;
        ASSERT_EQ(batch.size(), 1U);
        EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(batch[0]->timestamp), seq.timestamp(i));
        EXPECT_EQ(reader.recordsRead(), i + 1);
        EXPECT_DOUBLE_EQ(reader.fractionRead(), static_cast<double>(i + 1) / 4.0);
    }
    EXPECT_FALSE(reader.next(batch));
    EXPECT_TRUE(batch.empty());
    EXPECT_FALSE(reader.endedEarly());
    EXPECT_FALSE(reader.corrupt());
    EXPECT_EQ(reader.endReason(), "");
}

TEST(DatasetReadAhead, anUnreadableImageEndsTheInputEarly)
{
    const std::string root = emslam::test::makeTempDir("dataset_read_ahead_bad");
    const KittiSequence seq(emslam::test::writeKittiSequence(root, 4));
    const std::string bad = emslam::test::kittiFrameName(seq.directory(), "image_1", 2);
    emslam::test::writeFile(bad, "this is not a PNG file");
    DatasetReadAhead reader(seq);
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    EXPECT_TRUE(reader.next(batch));
    EXPECT_TRUE(reader.next(batch));
    EXPECT_FALSE(reader.endedEarly());
    EXPECT_FALSE(reader.next(batch));
    EXPECT_TRUE(batch.empty());
    EXPECT_EQ(reader.recordsRead(), 2U);
    EXPECT_TRUE(reader.endedEarly());
    EXPECT_TRUE(reader.corrupt());
    EXPECT_EQ(reader.endReason().rfind("frame 2: ", 0), 0U) << reader.endReason();
    EXPECT_NE(reader.endReason().find(bad), std::string::npos) << reader.endReason();
    EXPECT_FALSE(reader.next(batch));  // and stays ended
}
