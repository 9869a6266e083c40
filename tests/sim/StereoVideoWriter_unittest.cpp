// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/sim/StereoVideoWriter.h>

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>

using emslam::sim::StereoVideoWriter;
using emslam::test::expectThrowContaining;

namespace
{
cv::Mat noise(int seed)
{
    cv::Mat m(30, 40, CV_8UC1);
    cv::RNG rng(static_cast<uint64_t>(seed));
    rng.fill(m, cv::RNG::UNIFORM, 0, 256);
    return m;
}
}  // namespace

// FFV1 is lossless: every frame reads back as left | right, to the grey level.
TEST(StereoVideoWriter, writesLosslessSideBySideFrames)
{
    const std::string dir = emslam::test::makeTempDir("video_writer");
    for (const char* name : {"/v.avi", "/v.mkv"})
    {
        const std::string file = dir + name;
        {
            StereoVideoWriter w(file, 7.0, cv::Size(40, 30));
            for (int k = 0; k < 3; ++k)
            {
                w.write(noise(2 * k), noise(2 * k + 1));
            }
            EXPECT_EQ(w.framesWritten(), 3U);
        }
        cv::VideoCapture cap(file, cv::CAP_FFMPEG);
        ASSERT_TRUE(cap.isOpened()) << file;
        EXPECT_DOUBLE_EQ(cap.get(cv::CAP_PROP_FPS), 7.0);
        cv::Mat frame;
        int k = 0;
        while (cap.read(frame))
        {
            ASSERT_EQ(frame.cols, 80);
            ASSERT_EQ(frame.rows, 30);
            cv::Mat grey;
            cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
            EXPECT_EQ(cv::norm(grey.colRange(0, 40), noise(2 * k), cv::NORM_INF), 0.0) << k;
            EXPECT_EQ(cv::norm(grey.colRange(40, 80), noise(2 * k + 1), cv::NORM_INF), 0.0) << k;
            ++k;
        }
        EXPECT_EQ(k, 3) << file;
    }
}

TEST(StereoVideoWriter, refusesBadArgumentsNamingThem)
{
    const std::string dir = emslam::test::makeTempDir("video_writer_bad");
    expectThrowContaining(
        [&] { StereoVideoWriter(dir + "/a.avi", 5.0, cv::Size(40, 30), "FFV"); }, {"codec", "FFV"});
    expectThrowContaining(
        [&] { StereoVideoWriter(dir + "/a.avi", 0.0, cv::Size(40, 30)); }, {"fps"});
    expectThrowContaining(
        [&] { StereoVideoWriter(dir + "/no/such/dir/a.avi", 5.0, cv::Size(40, 30)); },
        {"no/such/dir/a.avi", "FFV1"});
    StereoVideoWriter w(dir + "/b.avi", 5.0, cv::Size(40, 30));
    expectThrowContaining(
        [&] { w.write(noise(0), cv::Mat(30, 41, CV_8UC1)); }, {"41x30", "expected 40x30"});
}
