// SPDX-License-Identifier: BSD-3-Clause
#include "PngWithSize.h"
#include "SimulatedHall.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/StereoApp.h>
#include <emslam/io/RawlogInput.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>
#include <vector>

namespace
{
// Debian's opencv-doc ships the Middlebury 2006 "Aloe" pair with ground truth.
const std::string ALOE_DIR = "/usr/share/doc/opencv-doc/examples/data/";

void runApp(emslam::apps::StereoApp& app, std::vector<std::string> args)
{
    args.insert(args.begin(), "emslam-stereo");
    std::vector<const char*> argv;
    for (const auto& a : args)
    {
        argv.push_back(a.c_str());
    }
    app.initialize(static_cast<int>(argv.size()), argv.data());
    app.run();
}

std::vector<std::string> aloeArgs()
{
    const std::string src = emslam::test::sourceDir();
    return {
        ALOE_DIR + "aloeL.jpg", ALOE_DIR + "aloeR.jpg",
        src + "/share/emslam/calib/middlebury-aloe.ini", "--config",
        src + "/config/stereo/middlebury-aloe.ini"};
}
}  // namespace

TEST(StereoApp, middleburyAloeDisparityIsAccurate)
{
    if (!mrpt::system::fileExists(ALOE_DIR + "aloeGT.png"))
    {
        GTEST_SKIP() << "Middlebury Aloe pair not installed (package opencv-doc)";
    }
    emslam::apps::StereoApp app;
    auto args = aloeArgs();
    args.insert(args.end(), {"--gt-disparity", ALOE_DIR + "aloeGT.png"});
    runApp(app, args);
    EXPECT_EQ(app.frames_processed, 1u);
    // Bad pixels (|d - d_gt| > 1 px at the 641x555 working size) among the
    // pixels that get a disparity. SGM-class matchers score 5-10 % on the
    // Middlebury 2006 scenes; we measured 5.6 % and guard regressions at 8 %.
    EXPECT_LT(app.bad_pixel_rate, 0.08);
    EXPECT_GE(app.bad_pixel_rate, 0.0);
    // Density: the filters keep most textured pixels; we measured ~75 %.
    EXPECT_GT(app.gt_coverage, 0.6);
    RecordProperty("bad_pixel_rate", std::to_string(app.bad_pixel_rate));
    RecordProperty("gt_coverage", std::to_string(app.gt_coverage));
}

TEST(StereoApp, writesAStockRangeScanRawlog)
{
    if (!mrpt::system::fileExists(ALOE_DIR + "aloeL.jpg"))
    {
        GTEST_SKIP() << "Middlebury Aloe pair not installed (package opencv-doc)";
    }
    const std::string dir = emslam::test::makeTempDir("stereo_app");
    emslam::apps::StereoApp app;
    auto args = aloeArgs();
    args.insert(args.end(), {"--out-rawlog", dir + "/out.rawlog", "--ply", dir + "/out.ply"});
    runApp(app, args);
    mrpt::io::CFileGZInputStream in(dir + "/out.rawlog");
    auto arch = mrpt::serialization::archiveFrom(in);
    const auto obs = arch.ReadObject<mrpt::obs::CObservation3DRangeScan>();
    ASSERT_TRUE(obs);
    EXPECT_EQ(obs->points3D_x.size(), app.total_points);
    EXPECT_TRUE(obs->hasIntensityImage);
    EXPECT_FALSE(mrpt::system::fileExists(dir + "/out.rawlog.partial"));
    EXPECT_GT(mrpt::system::getFileSize(dir + "/out.ply"), 1000u);
}

TEST(StereoApp, badInputsFailWithAClearError)
{
    const std::string dir = emslam::test::makeTempDir("stereo_app_bad");
    const std::string calib = emslam::test::sourceDir() + "/share/emslam/calib/middlebury-aloe.ini";
    {
        emslam::apps::StereoApp app;
        try
        {
            runApp(app, {dir + "/nope.png", dir + "/nope.png", calib});
            FAIL() << "missing image accepted";
        }
        catch (const std::exception& e)
        {
            EXPECT_NE(std::string(e.what()).find("nope.png"), std::string::npos) << e.what();
        }
    }
    {
        std::ofstream(dir + "/garbage.png") << "not an image";
        emslam::apps::StereoApp app;
        EXPECT_THROW(
            runApp(app, {dir + "/garbage.png", dir + "/garbage.png", calib}), std::exception);
    }
    {
        // A huge size in the header is refused before decoding (80c9fba decoded it).
        emslam::test::writePngDeclaring(dir + "/huge.png", 30000, 30000);
        emslam::apps::StereoApp app;
        emslam::test::expectThrowContaining(
            [&] {
                runApp(app, {dir + "/huge.png", dir + "/huge.png", calib});
            },
            {"left image", "huge.png' is 30000x30000 (PNG header)", "not decoded"});
    }
    {
        emslam::apps::StereoApp app;  // neither a pair nor a rawlog
        EXPECT_THROW(runApp(app, {}), std::invalid_argument);
    }
    {
        emslam::apps::StereoApp app;
        EXPECT_THROW(runApp(app, {dir + "/missing.rawlog"}), std::exception);
    }
    {
        emslam::apps::StereoApp app;
        EXPECT_THROW(runApp(app, {"--no-such-option"}), std::invalid_argument);
    }
    {
        emslam::apps::StereoApp app;
        EXPECT_THROW(runApp(app, {"x", "--set", "nodot"}), std::invalid_argument);
    }
}

TEST(StereoApp, helpDoesNotRun)
{
    emslam::apps::StereoApp app;
    runApp(app, {"--help"});
    EXPECT_TRUE(app.helpRequested());
    EXPECT_EQ(app.frames_processed, 0u);
}

// A rawlog with a repeated stamp (frame 2), a frame of another camera (4), a
// frame the front-end refuses (6: right image 160x120) and a stamp 1 s back
// (8): those four are skipped and counted, the others written in time order.
// A camera changed for good (from frame 6 on) is followed as far as the first
// one goes.
TEST(StereoApp, rawlogFramesWithBadStampsOrCamerasAreSkipped)
{
    const std::string dir = emslam::test::makeTempDir("stereo_app_skip");
    const std::string rawlog = dir + "/in.rawlog";
    mrpt::Clock::time_point previous;
    emslam::test::writeEditedHall(
        rawlog, 12,
        [&](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
        {
            const auto own = stereo.timestamp;
            if (i == 2)
            {
                stereo.timestamp = previous;
            }
            if (i == 4)
            {
                emslam::test::resizeStereoFrame(stereo, 640, 480);
            }
            if (i == 6)
            {
                emslam::test::shrinkRightImage(stereo);
            }
            if (i == 8)
            {
                stereo.timestamp = own - std::chrono::seconds(1);
            }
            previous = own;
        });
    emslam::apps::StereoApp app;
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    runApp(app, {rawlog, "--out-rawlog", dir + "/out.rawlog"});
    testing::internal::GetCapturedStdout();
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(app.frames_processed, 8U);
    EXPECT_EQ(app.skipped.bad_stamps, 2U);
    EXPECT_EQ(app.skipped.camera_changes, 1U);
    EXPECT_EQ(app.skipped.unusable, 1U);
    ASSERT_EQ(app.skipped_reasons.size(), 4U);
    EXPECT_EQ(app.skipped_reasons[0].rfind("record 2: its timestamp", 0), 0U);
    EXPECT_EQ(app.skipped_reasons[1].rfind("record 4: its camera 640x480", 0), 0U);
    EXPECT_EQ(app.skipped_reasons[2].rfind("record 6: stereo observation", 0), 0U);
    EXPECT_EQ(app.skipped_reasons[3].rfind("record 8: its timestamp", 0), 0U);
    EXPECT_NE(
        err.find("emslam-stereo: warning: skipping unusable observation at record 6: "),
        std::string::npos)
        << err;
    EXPECT_NE(
        err.find("emslam-stereo: warning: 1 frame skipped: their camera differed"),
        std::string::npos)
        << err;

    emslam::io::RawlogInput out(dir + "/out.rawlog");
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    std::vector<double> stamps;
    while (out.next(batch))
    {
        for (const auto& o : batch)
        {
            stamps.push_back(mrpt::Clock::toDouble(o->timestamp));
        }
    }
    ASSERT_EQ(stamps.size(), 8U);
    for (std::size_t i = 1; i < stamps.size(); ++i)
    {
        EXPECT_GT(stamps[i], stamps[i - 1]) << i;
    }

    const std::string changed = dir + "/changed.rawlog";
    emslam::test::writeEditedHall(
        changed, 12,
        [](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
        {
            if (i >= 6)
            {
                emslam::test::resizeStereoFrame(stereo, 640, 480);
            }
        });
    emslam::apps::StereoApp app2;
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    runApp(app2, {changed});
    testing::internal::GetCapturedStdout();
    testing::internal::GetCapturedStderr();
    EXPECT_EQ(app2.frames_processed, 6U);
    EXPECT_EQ(app2.skipped.camera_changes, 6U);
    EXPECT_EQ(app2.camera_change.rfind("6 frames skipped: camera changed from 320x240", 0), 0U)
        << app2.camera_change;
}
