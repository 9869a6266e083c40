// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/hwdrivers/CSimulatedStereoCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservationStereoImages.h>

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <string>
#include <vector>

using emslam::hwdrivers::CSimulatedStereoCamera;

namespace
{
std::string worldFile()
{
    return emslam::test::sourceDir() + "/config/sim/hall_double_loop.ini";
}

std::string ini(const std::string& extra)
{
    return "[SIM]\ndriver = CSimulatedStereoCamera\nsensorLabel = SIMCAM\nworld_file = " +
           worldFile() + "\n" + extra;
}

std::vector<mrpt::obs::CObservationStereoImages::Ptr> drain(CSimulatedStereoCamera& cam)
{
    std::vector<mrpt::obs::CObservationStereoImages::Ptr> out;
    for (const auto& [t, o] : cam.getObservations())
    {
        out.push_back(std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(o));
    }
    return out;
}
}  // namespace

TEST(CSimulatedStereoCamera, loadsKeysAndRoundTrips)
{
    const mrpt::config::CConfigFileMemory c(
        ini("first_frame = 3\nmax_frames = 7\nloop = true\ntimestamps = simulation\n"));
    CSimulatedStereoCamera::TParameters p;
    p.loadFromConfigFile(c, "SIM");
    EXPECT_EQ(p.world_file, worldFile());
    EXPECT_EQ(p.first_frame, 3U);
    EXPECT_EQ(p.max_frames, 7U);
    EXPECT_TRUE(p.loop);
    EXPECT_EQ(p.timestamps, "simulation");
    mrpt::config::CConfigFileMemory out;
    p.saveToConfigFile(out, "X");
    const mrpt::config::CConfigFileMemory reparsed(out.getContent());
    CSimulatedStereoCamera::TParameters q;
    q.loadFromConfigFile(reparsed, "X");
    EXPECT_EQ(q.world_file, p.world_file);
    EXPECT_EQ(q.first_frame, p.first_frame);
    EXPECT_EQ(q.max_frames, p.max_frames);
    EXPECT_EQ(q.loop, p.loop);
    EXPECT_EQ(q.timestamps, p.timestamps);
}

TEST(CSimulatedStereoCamera, invalidValuesThrow)
{
    using emslam::test::expectThrowContaining;
    CSimulatedStereoCamera cam;
    expectThrowContaining(
        [&]
        { cam.loadConfig(mrpt::config::CConfigFileMemory("[SIM]\nprocess_rate = 5\n"), "SIM"); },
        {"world_file", "mandatory"});
    expectThrowContaining(
        [&]
        {
            cam.loadConfig(
                mrpt::config::CConfigFileMemory("[SIM]\nworld_file = /no/such/world.ini\n"), "SIM");
        },
        {"/no/such/world.ini", "does not exist"});
    expectThrowContaining(
        [&] { cam.loadConfig(mrpt::config::CConfigFileMemory(ini("timestamps = gps\n")), "SIM"); },
        {"timestamps", "gps"});
    expectThrowContaining(
        [&]
        { cam.loadConfig(mrpt::config::CConfigFileMemory(ini("first_frame = 100000\n")), "SIM"); },
        {"first_frame 100000"});
    // MRPT's read_uint64_t would wrap -1 to 2^64 - 1 (and first_frame +
    // max_frames to 1: zero frames, silently).
    expectThrowContaining(
        [&] { cam.loadConfig(mrpt::config::CConfigFileMemory(ini("max_frames = -1\n")), "SIM"); },
        {"max_frames = '-1'", "whole number"});
    expectThrowContaining(
        [&] { cam.loadConfig(mrpt::config::CConfigFileMemory(ini("first_frame = 1e3\n")), "SIM"); },
        {"first_frame = '1e3'", "whole number"});
    EXPECT_THROW(cam.doProcess(), std::logic_error);
}

TEST(CSimulatedStereoCamera, rendersTheWorldFramesThenEnds)
{
    auto s = mrpt::hwdrivers::CGenericSensor::createSensorPtr("CSimulatedStereoCamera");
    ASSERT_TRUE(s);
    auto& cam = dynamic_cast<CSimulatedStereoCamera&>(*s);
    cam.loadConfig(
        mrpt::config::CConfigFileMemory(
            ini("first_frame = 2\nmax_frames = 3\ntimestamps = simulation\n")),
        "SIM");
    // No process_rate in the INI: the world's fps (5).
    EXPECT_EQ(cam.getProcessRate(), 5.0);
    for (int i = 0; i < 3; ++i)
    {
        cam.doProcess();
    }
    EXPECT_THROW(cam.doProcess(), emslam::hwdrivers::EndOfStream);
    const auto obs = drain(cam);
    ASSERT_EQ(obs.size(), 3U);
    const auto& sim = cam.simulator();
    for (std::size_t i = 0; i < 3; ++i)
    {
        ASSERT_TRUE(obs[i]);
        EXPECT_EQ(obs[i]->sensorLabel, "SIMCAM");
        EXPECT_TRUE(obs[i]->hasImageRight);
        EXPECT_EQ(obs[i]->imageLeft.getWidth(), 320U);
        EXPECT_EQ(obs[i]->leftCamera.fx(), 200.0);
        EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(obs[i]->timestamp), sim.frameTime(i + 2));
        // The same pixels as the simulator's own frame.
        const auto ref = sim.renderFrame(i + 2);
        EXPECT_EQ(
            cv::norm(obs[i]->imageLeft.asCvMatRef(), ref.obs->imageLeft.asCvMatRef(), cv::NORM_INF),
            0.0);
    }
    EXPECT_EQ(cam.framesDelivered(), 3U);
}

TEST(CSimulatedStereoCamera, loopsAndStampsWithTheWallClock)
{
    CSimulatedStereoCamera cam;
    cam.loadConfig(
        mrpt::config::CConfigFileMemory(ini("process_rate = 50\nmax_frames = 2\nloop = true\n")),
        "SIM");
    EXPECT_EQ(cam.getProcessRate(), 50.0);
    const auto before = mrpt::Clock::now();
    for (int i = 0; i < 5; ++i)
    {
        cam.doProcess();
    }
    const auto obs = drain(cam);
    ASSERT_EQ(obs.size(), 5U);
    // Frames 0 1 0 1 0: the first and third are the same picture.
    EXPECT_EQ(
        cv::norm(obs[0]->imageLeft.asCvMatRef(), obs[2]->imageLeft.asCvMatRef(), cv::NORM_INF),
        0.0);
    EXPECT_GT(
        cv::norm(obs[0]->imageLeft.asCvMatRef(), obs[1]->imageLeft.asCvMatRef(), cv::NORM_INF),
        0.0);
    for (const auto& o : obs)
    {
        EXPECT_GE(o->timestamp, before);
    }
}
