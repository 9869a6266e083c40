// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/BackgroundWorker.h>

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>

using emslam::slam::BackgroundWorker;

TEST(BackgroundWorker, drainWaitsForTheJobAfterEveryNotification)
{
    std::atomic<int> items{0}, taken{0};
    BackgroundWorker w([&] { taken = items.load(); });
    for (int k = 1; k <= 100; ++k)
    {
        items = k;
        w.notify();
    }
    w.drain();
    EXPECT_EQ(taken.load(), 100);  // the last run saw every item
    EXPECT_EQ(w.pending(), 0u);
    w.stop();
    w.stop();  // idempotent
}

TEST(BackgroundWorker, anExceptionOfTheJobReachesTheCaller)
{
    BackgroundWorker w([] { throw std::runtime_error("job failed"); });
    w.notify();
    EXPECT_THROW(w.drain(), std::runtime_error);
    EXPECT_NO_THROW(w.stop());  // reported once
}
