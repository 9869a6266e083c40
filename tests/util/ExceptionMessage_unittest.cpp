// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/core/exceptions.h>

#include <gtest/gtest.h>

#include <stdexcept>

using emslam::util::shortExceptionMessage;

TEST(ExceptionMessage, plainExceptionsKeepTheirText)
{
    EXPECT_EQ(
        shortExceptionMessage(std::runtime_error("  file 'x' is missing\n")),
        "file 'x' is missing");
}

TEST(ExceptionMessage, mrptExceptionsLoseLocationAndBacktrace)
{
    try
    {
        THROW_EXCEPTION("calibration 'c.ini' has no [CAM_LEFT] section");
    }
    catch (const std::exception& e)
    {
        ASSERT_NE(std::string(e.what()).find("Location:"), std::string::npos);
        EXPECT_EQ(shortExceptionMessage(e), "calibration 'c.ini' has no [CAM_LEFT] section");
    }
}

TEST(ExceptionMessage, severalMessageLinesAreJoinedOutermostFirst)
{
    const std::runtime_error e(
        "==== MRPT exception ====\nMessage:  outer context\nLocation: a.cpp:1\n"
        "Message:  inner cause\nCall stack backtrace:\n[0] 0x1\n");
    EXPECT_EQ(shortExceptionMessage(e), "outer context: inner cause");
}

// MRPT_END wraps an exception of ours thrown below an archive (a write error
// in a gz stream): the text stays, the backtrace goes.
TEST(ExceptionMessage, wrappedStdExceptionsLoseTheBacktrace)
{
    try
    {
        MRPT_START
        throw std::runtime_error("cannot write 'o.rawlog': No space left on device");
        MRPT_END
    }
    catch (const std::exception& e)
    {
        ASSERT_NE(std::string(e.what()).find("Call stack backtrace:"), std::string::npos);
        EXPECT_EQ(shortExceptionMessage(e), "cannot write 'o.rawlog': No space left on device");
    }
}
