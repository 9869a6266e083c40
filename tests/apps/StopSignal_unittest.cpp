// SPDX-License-Identifier: BSD-3-Clause
// A run stopped by a signal remembers which one, and its main exits with
// 128 + that signal (130 after Ctrl-C); a stop asked by code exits 0.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/StopSignal.h>

#include <gtest/gtest.h>

#include <csignal>
#include <stdexcept>

namespace
{
using emslam::apps::StopSignal;
using emslam::apps::StopSignalGuard;

/** An app whose run() stops as a long loop does when `T_SIGNAL` arrives
 * (0: when asked to by code). */
template <int T_SIGNAL>
struct StoppedApp
{
    void initialize(int /*argc*/, char** /*argv*/) {}
    void run()
    {
        StopSignal::clear();
        const StopSignalGuard signals;
        if (T_SIGNAL != 0)
        {
            std::raise(T_SIGNAL);
        }
        else
        {
            StopSignal::request();
        }
        if (!StopSignal::requested())
        {
            throw std::logic_error("the stop was lost");
        }
    }
};

int runMain(int (*main_body)(const char*, int, char**))
{
    char program[] = "emslam-test";
    char* argv[] = {program, nullptr};
    return main_body("emslam-test", 1, argv);
}
}  // namespace

TEST(StopSignal, remembersTheSignalUntilCleared)
{
    StopSignal::clear();
    {
        const StopSignalGuard signals;
        std::raise(SIGTERM);
    }
    EXPECT_TRUE(StopSignal::requested());
    EXPECT_EQ(StopSignal::receivedSignal(), SIGTERM);
    StopSignal::clear();
    EXPECT_FALSE(StopSignal::requested());
    EXPECT_EQ(StopSignal::receivedSignal(), 0);
}

TEST(StopSignal, aHangupStopsAsATermDoes)
{
    // A dropped ssh session: the run stops and keeps its work.
    StopSignal::clear();
    {
        const StopSignalGuard signals;
        std::raise(SIGHUP);
    }
    EXPECT_TRUE(StopSignal::requested());
    EXPECT_EQ(StopSignal::receivedSignal(), SIGHUP);
    StopSignal::clear();
}

TEST(StopSignal, appMainExitsWith128PlusTheSignal)
{
    EXPECT_EQ(runMain(&emslam::apps::appMain<StoppedApp<SIGINT>>), 130);
    EXPECT_EQ(runMain(&emslam::apps::appMain<StoppedApp<SIGTERM>>), 143);
    EXPECT_EQ(runMain(&emslam::apps::appMain<StoppedApp<0>>), 0);
    StopSignal::clear();
}
