// SPDX-License-Identifier: BSD-3-Clause
// emslam-mapview's loading: entropy_map.bin and .3Dscene files become scenes
// (the window itself is covered by the LiveViewer test); bad files fail
// naming the file and the cause; no window (no display, no OpenGL) fails the
// program.
#include "MapDrawingFixture.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/EntropyVoxelObject.h>
#include <emslam/apps/MapScene.h>
#include <emslam/apps/MapViewApp.h>

#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

using emslam::apps::MapViewApp;

TEST(MapViewApp, opensEntropyMapBinAndScenes)
{
    const emslam::test::MapDrawingFixture f;
    const std::string dir = emslam::test::makeTempDir("mapview");
    {
        mrpt::io::CFileOutputStream out(dir + "/entropy_map.bin");
        mrpt::serialization::archiveFrom(out) << f.entropy_map;
    }
    const auto scene = MapViewApp::loadScene(dir + "/entropy_map.bin", 300);
    const auto voxels = std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(
        scene->getByName(emslam::apps::ENTROPY_VOXELS_NAME));
    ASSERT_TRUE(voxels);
    const auto cells =
        std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(*voxels->begin());
    ASSERT_TRUE(cells);
    EXPECT_EQ(cells->size(), 300U);  // bounded by --max-cells

    emslam::apps::writeMapScene(f.content(), dir + "/map.3Dscene");
    const auto map_scene = MapViewApp::loadScene(dir + "/map.3Dscene", 300);
    EXPECT_TRUE(map_scene->getByName(emslam::apps::LEGEND_NAME));
}

TEST(MapViewApp, badFilesFailNamingTheFileAndCause)
{
    const std::string dir = emslam::test::makeTempDir("mapview_bad");
    emslam::test::expectThrowContaining(
        [&] { MapViewApp::loadScene(dir + "/none.bin", 10); }, {"none.bin", "does not exist"});
    emslam::test::writeFile(dir + "/text.bin", "not a map\n");
    emslam::test::expectThrowContaining(
        [&] { MapViewApp::loadScene(dir + "/text.bin", 10); },
        {"text.bin", "not a serialized MRPT object"});
    {
        mrpt::io::CFileOutputStream out(dir + "/odometry.bin");
        mrpt::serialization::archiveFrom(out) << mrpt::obs::CObservationOdometry();
    }
    emslam::test::expectThrowContaining(
        [&] { MapViewApp::loadScene(dir + "/odometry.bin", 10); },
        {"odometry.bin", "CObservationOdometry", "not a metric map"});
    emslam::test::writeFile(dir + "/bad.3Dscene", "not a scene\n");
    emslam::test::expectThrowContaining(
        [&] { MapViewApp::loadScene(dir + "/bad.3Dscene", 10); },
        {"bad.3Dscene", "not a readable .3Dscene"});
}

#ifdef EMSLAM_MAPVIEW_EXE
namespace
{
/** A small scene file to show. */
std::string sceneFile(const std::string& tag)
{
    const emslam::test::MapDrawingFixture f;
    const std::string file = emslam::test::makeTempDir(tag) + "/map.3Dscene";
    emslam::apps::writeMapScene(f.content(), file);
    return file;
}
}  // namespace

// Nothing to show the scene on: a clear error and exit status 1, not 0.
TEST(MapViewApp, noDisplayExitsNonZeroWithTheReason)
{
    const std::string file = sceneFile("mapview_no_display");
    const auto run =
        emslam::test::runProgram("/usr/bin/env", {"-u", "DISPLAY", EMSLAM_MAPVIEW_EXE, file});
    EXPECT_EQ(run.exit_code, 1) << run.stderr_text;
    EXPECT_NE(
        run.stderr_text.find(
            "emslam-mapview: error: cannot show '" + file + "': DISPLAY is not set"),
        std::string::npos)
        << run.stderr_text;
}

// A display without OpenGL (an Xvfb without its GLX extension): the window
// toolkit only times out (5 s), so the program checks the window opened.
TEST(MapViewApp, noOpenGlWindowExitsNonZeroWithTheReason)
{
    if (emslam::test::runProgram("/bin/sh", {"-c", "command -v xvfb-run"}).exit_code != 0)
    {
        GTEST_SKIP() << "xvfb-run not installed";
    }
    const std::string file = sceneFile("mapview_no_glx");
    const auto run = emslam::test::runProgram(
        "/usr/bin/env", {"xvfb-run", "-a", "-s", "-extension GLX", EMSLAM_MAPVIEW_EXE, file});
    EXPECT_EQ(run.exit_code, 1) << run.stderr_text;
    EXPECT_NE(
        run.stderr_text.find(
            "emslam-mapview: error: cannot show '" + file + "': no window opened on display"),
        std::string::npos)
        << run.stderr_text;
}
// --screenshot draws off-screen: an image of the scene without any display.
TEST(MapViewApp, screenshotNeedsNoDisplay)
{
    const std::string file = sceneFile("mapview_screenshot");
    const std::string png = file + ".png";
    const auto run = emslam::test::runProgram(
        "/usr/bin/env", {"-u", "DISPLAY", EMSLAM_MAPVIEW_EXE, file, "--screenshot", png});
    ASSERT_EQ(run.exit_code, 0) << run.stderr_text;
    const cv::Mat image = cv::imread(png, cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << png;
    EXPECT_EQ(image.cols, 1000);
    EXPECT_EQ(image.rows, 700);
    // Something drawn on the background, not one flat colour.
    cv::Scalar mean, stddev;
    cv::meanStdDev(image, mean, stddev);
    EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 10.0);
    const auto bad = emslam::test::runProgram(
        "/usr/bin/env",
        {"-u", "DISPLAY", EMSLAM_MAPVIEW_EXE, file, "--screenshot", file + "/no/such/dir.png"});
    EXPECT_EQ(bad.exit_code, 1) << bad.stderr_text;
    EXPECT_NE(bad.stderr_text.find("cannot write the screenshot"), std::string::npos)
        << bad.stderr_text;
}
#endif
