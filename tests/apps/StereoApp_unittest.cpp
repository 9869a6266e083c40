// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"

#include <emslam/apps/StereoApp.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <gtest/gtest.h>

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
