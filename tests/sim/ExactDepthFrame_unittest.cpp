// SPDX-License-Identifier: BSD-3-Clause
#include "SimTestWorlds.h"
#include "TestHelpers.h"

#include <emslam/sim/ExactDepthFrame.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

using emslam::sim::StereoSimulator;

TEST(ExactDepthFrame, everyPointIsItsPixelsRayAtTheRenderedDepth)
{
    mrpt::config::CConfigFileMemory c(emslam::test::tinyWorldIni());
    StereoSimulator sim;
    sim.load(c);
    const auto f = sim.renderFrame(10, true);
    const auto s = emslam::sim::exactDepthFrame(f, 0.3, 6.0);
    ASSERT_GT(s.size(), 1000u);
    ASSERT_EQ(s.pixels.size(), s.size());
    EXPECT_EQ(cv::countNonZero(s.valid), static_cast<int>(s.size()));
    const auto& cam = s.camera.leftCamera;
    std::size_t in_range = 0;
    for (int v = 0; v < f.depth.rows; ++v)
    {
        for (int u = 0; u < f.depth.cols; ++u)
        {
            const float z = f.depth.at<float>(v, u);
            in_range += z >= 0.3f && z <= 6.0f ? 1 : 0;
        }
    }
    EXPECT_EQ(s.size(), in_range);  // every pixel within range, no other
    for (std::size_t i = 0; i < s.size(); i += 97)
    {
        const auto& p = s.points[i];
        const auto& px = s.pixels[i];
        EXPECT_NEAR(p.z, f.depth.at<float>(px.v, px.u), 1e-6);
        EXPECT_NEAR(cam.fx() * p.x / p.z + cam.cx(), px.u, 1e-3);
        EXPECT_NEAR(cam.fy() * p.y / p.z + cam.cy(), px.v, 1e-3);
        EXPECT_GE(p.z, 0.3f);
        EXPECT_LE(p.z, 6.0f);
    }
    EXPECT_EQ(s.intensity.size(), f.depth.size());
    EXPECT_EQ(s.timestamp, f.obs->timestamp);

    emslam::test::expectThrowContaining(
        [&] { emslam::sim::exactDepthFrame(sim.renderFrame(10, false), 0.3, 6.0); },
        {"without its depth"});
}
