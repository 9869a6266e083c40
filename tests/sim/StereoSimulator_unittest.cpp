// SPDX-License-Identifier: BSD-3-Clause
#include "SimTestWorlds.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/sim/StereoSimulator.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>

using emslam::sim::StereoSimulator;

TEST(StereoSimulator, everyShippedWorldLoadsAndRenders)
{
    const auto worlds = emslam::test::shippedSimWorlds();
    ASSERT_GE(worlds.size(), 6U);
    for (const auto& w : worlds)
    {
        SCOPED_TRACE(w);
        StereoSimulator sim;
        ASSERT_NO_THROW(sim.loadFile(w));
        EXPECT_GT(sim.frameCount(), 50U);
        const auto f = sim.renderFrame(sim.frameCount() / 3, true);
        ASSERT_TRUE(f.obs);
        EXPECT_TRUE(f.obs->hasImageRight);
        EXPECT_EQ(f.obs->sensorLabel, "STEREO");
        EXPECT_EQ(f.obs->imageLeft.getWidth(), 320U);
        EXPECT_EQ(f.obs->imageLeft.getHeight(), 240U);
        EXPECT_EQ(f.obs->leftCamera.fx(), 200.0);
        // Mostly textured surfaces within range.
        EXPECT_GT(cv::countNonZero(f.depth > 0), 320 * 240 / 3);
        cv::Mat gx;
        cv::Sobel(f.obs->imageLeft.asCvMatRef(), gx, CV_32F, 1, 0);
        EXPECT_GT(cv::mean(cv::abs(gx))[0], 5.0);
        // Consecutive frames overlap like the paper's data (<= 0.5 m, <= 15 deg).
        for (std::size_t i = 1; i < sim.frameCount(); i += 7)
        {
            const auto d = sim.groundTruth(i) - sim.groundTruth(i - 1);
            EXPECT_LE(d.norm(), 0.5);
        }
    }
}

TEST(StereoSimulator, everyShippedLoopEndsWhereItStarts)
{
    // The loop worlds of the paper's experiments: the ground truth's first and
    // last poses coincide (within 5 cm and 1 deg), whatever the frame rate.
    std::size_t loops = 0;
    for (const auto& w : emslam::test::shippedSimWorlds())
    {
        StereoSimulator sim;
        sim.loadFile(w);
        if (!sim.trajectory().params().closed)
        {
            continue;
        }
        SCOPED_TRACE(w);
        ++loops;
        const auto last = sim.groundTruth(sim.frameCount() - 1);
        EXPECT_LT(last.norm(), 0.05);
        const auto R = last.getRotationMatrix();
        EXPECT_LT(
            std::acos(std::clamp((R(0, 0) + R(1, 1) + R(2, 2) - 1) / 2, -1.0, 1.0)),
            1.0 * M_PI / 180);
    }
    EXPECT_GE(loops, 6U);  // the hall, outdoor_ground and the four loops of section 3
}

TEST(StereoSimulator, groundTruthStartsAtIdentityAndTimestampsFollowFps)
{
    mrpt::config::CConfigFileMemory c(emslam::test::tinyWorldIni());
    StereoSimulator sim;
    sim.load(c);
    // 6 m at 0.5 m/s at 5 fps: 60 intervals.
    EXPECT_EQ(sim.frameCount(), 61U);
    EXPECT_EQ(sim.groundTruth(0).norm(), 0.0);
    EXPECT_DOUBLE_EQ(sim.frameTime(5) - sim.frameTime(0), 1.0);
    // The robot drives straight forward: +z in the first camera frame.
    const auto g = sim.groundTruth(60);
    EXPECT_NEAR(g.z(), 6.0, 1e-9);
    EXPECT_NEAR(g.x(), 0.0, 1e-9);
    EXPECT_NEAR(g.y(), 0.0, 1e-9);
    const auto f = sim.renderFrame(3);
    EXPECT_NEAR(mrpt::Clock::toDouble(f.obs->timestamp), 1700000000.0 + 0.6, 1e-5);
    EXPECT_THROW(sim.renderFrame(61), std::out_of_range);
}

TEST(StereoSimulator, renderingIsDeterministic)
{
    mrpt::config::CConfigFileMemory c(emslam::test::tinyWorldIni());
    StereoSimulator a;
    StereoSimulator b;
    a.load(c);
    b.load(c);
    const auto fa = a.renderFrame(7);
    const auto fb = b.renderFrame(7);
    EXPECT_EQ(
        cv::norm(fa.obs->imageLeft.asCvMatRef(), fb.obs->imageLeft.asCvMatRef(), cv::NORM_INF),
        0.0);
    EXPECT_EQ(
        cv::norm(fa.obs->imageRight.asCvMatRef(), fb.obs->imageRight.asCvMatRef(), cv::NORM_INF),
        0.0);
}

TEST(StereoSimulator, movingObjectMoves)
{
    StereoSimulator sim;
    sim.loadFile(emslam::test::sourceDir() + "/config/sim/moving_object.ini");
    const auto& e = sim.world().elements().back();
    ASSERT_TRUE(e.moving());
    // Same camera pose, different times: the depth changes where the box passes.
    const auto pose = sim.scenePose(20);
    const auto f1 = sim.renderer().render(sim.world(), pose, 4.0, 1.0, 1, true);
    const auto f2 = sim.renderer().render(sim.world(), pose, 6.0, 1.0, 1, true);
    const auto f3 = sim.renderer().render(sim.world(), pose, 6.0, 1.0, 1, true);
    EXPECT_GT(cv::countNonZero(cv::abs(f1.depth - f2.depth) > 1.0), 200);
    EXPECT_EQ(cv::countNonZero(cv::abs(f3.depth - f2.depth) > 0.0), 0);
}

TEST(StereoSimulator, badIniNamesTheKey)
{
    using emslam::test::expectThrowContaining;
    auto load = [](const std::string& text)
    {
        mrpt::config::CConfigFileMemory c(text);
        StereoSimulator s;
        s.load(c);
    };
    expectThrowContaining(
        [&] { load(emslam::test::tinyWorldIni("[Camera]\nbaseline = -0.1\n")); },
        {"[Camera] baseline"});
    expectThrowContaining(
        [&] { load(emslam::test::tinyWorldIni("[Simulation]\nfps = 0.5\n")); },
        {"[Simulation] fps", "max_step"});
    expectThrowContaining(
        [&] { load(emslam::test::tinyWorldIni("[Trajectory]\nwaypoints =\n")); },
        {"[Trajectory] waypoints"});
    expectThrowContaining(
        [&] { load(emslam::test::tinyWorldIni("[World]\ntype = cave\n")); }, {"[World] type"});
    expectThrowContaining(
        [] { StereoSimulator().loadFile("/nonexistent/world.ini"); }, {"/nonexistent/world.ini"});
}

TEST(StereoSimulator, parametersSaveLoadRoundTrip)
{
    StereoSimulator::TParameters p;
    p.fps = 12;
    p.sensor_label = "CAM";
    p.exposure_amplitude = 0.2;
    mrpt::config::CConfigFileMemory c;
    p.saveToConfigFile(c, "Simulation");
    mrpt::config::CConfigFileMemory r(c.getContent());
    StereoSimulator::TParameters q;
    q.loadFromConfigFile(r, "Simulation");
    EXPECT_EQ(q.fps, 12.0);
    EXPECT_EQ(q.sensor_label, "CAM");
    EXPECT_EQ(q.exposure_amplitude, 0.2);
}
