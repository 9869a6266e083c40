// SPDX-License-Identifier: BSD-3-Clause
#include "SimTestWorlds.h"

#include <emslam/sim/StereoSimulator.h>
#include <emslam/sim/SurfaceSampler.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

using emslam::sim::Element;
using emslam::sim::StereoSimulator;
using emslam::sim::SurfaceSample;
using emslam::sim::SurfaceSampler;
using emslam::sim::Vec3;

namespace
{
/** Distance from `p` to the element's surface (a plane's rectangle or a
 * box's six faces) [m]. */
double distanceToSurface(const Element& e, const Vec3& p)
{
    double outside2 = 0;       // squared distance to the solid [lo, hi]
    double inside = HUGE_VAL;  // distance to the nearest face from inside
    for (std::size_t a = 0; a < 3; ++a)
    {
        const double d = std::max({e.lo[a] - p[a], p[a] - e.hi[a], 0.0});
        outside2 += d * d;
        inside = std::min({inside, p[a] - e.lo[a], e.hi[a] - p[a]});
    }
    return outside2 > 0 ? std::sqrt(outside2) : std::max(inside, 0.0);
}

StereoSimulator corridorWithBlock()
{
    // A 0.5 m block on the right of a corridor the camera drives along +z:
    // its back face (z = 7.5) and its top (y = 2, above the camera) face away.
    mrpt::config::CConfigFileMemory cfg(
        emslam::test::tinyWorldIni("[Element_block]\ntype = box\nmin = 2 0 7\nmax = 2.5 2 7.5\n"));
    StereoSimulator sim;
    sim.load(cfg);
    return sim;
}
}  // namespace

TEST(SurfaceSampler, samplesEveryFaceOnAGridOfTheSpacing)
{
    emslam::sim::World w;
    Element plane;
    plane.kind = Element::Kind::Plane;
    plane.axis = 2;
    plane.lo = {0, 0, 3};
    plane.hi = {1, 0.5, 3};
    w.addElement(plane);
    Element box = plane;
    box.kind = Element::Kind::Box;
    box.lo = {5, 0, 5};
    box.hi = {6, 1, 6};
    w.addElement(box);
    SurfaceSampler::TParameters p;
    p.spacing = 0.1;
    const auto s = SurfaceSampler(p).allSurfaces(w);
    // 10 x 5 on the plane, 6 faces of 10 x 10 on the box.
    ASSERT_EQ(s.size(), 50U + 600U);
    for (std::size_t k = 0; k < 50; ++k)
    {
        EXPECT_DOUBLE_EQ(s[k].position[2], 3.0);
        EXPECT_DOUBLE_EQ(s[k].normal[2], 1.0);
        EXPECT_NEAR(std::fmod(s[k].position[0] + 1e-9, 0.1), 0.05, 1e-6);  // cell centres
    }
    for (std::size_t k = 50; k < s.size(); ++k)
    {
        EXPECT_NEAR(distanceToSurface(box, s[k].position), 0.0, 1e-12);
    }
}

TEST(SurfaceSampler, visibleSamplesLieOnTheTrueSurfacesTheCameraSaw)
{
    const StereoSimulator sim = corridorWithBlock();
    SurfaceSampler::TParameters p;
    p.spacing = 0.05;
    p.max_range = 8.0;
    const SurfaceSampler sampler(p);
    const auto seen = sampler.visibleSurfaces(sim, sim.frameCount());
    const auto all = sampler.allSurfaces(sim.world());
    ASSERT_GT(seen.size(), all.size() / 10);
    ASSERT_LT(seen.size(), all.size());
    const auto T_scene_first = sim.scenePose(0);
    const auto& block = sim.world().elements().back();
    std::size_t front = 0;
    for (const SurfaceSample& s : seen)
    {
        // Back in the scene frame, the sample is on a surface of the world.
        Vec3 q;
        T_scene_first.composePoint(s.position[0], s.position[1], s.position[2], q[0], q[1], q[2]);
        double d = HUGE_VAL;
        for (const auto& e : sim.world().elements())
        {
            d = std::min(d, distanceToSurface(e, q));
        }
        ASSERT_LT(d, 1e-6);
        EXPECT_GE(s.seen_range, 0.3F);
        EXPECT_LE(s.seen_range, 8.0F);
        EXPECT_NEAR(std::hypot(s.normal[0], s.normal[1], s.normal[2]), 1.0, 1e-9);
        if (distanceToSurface(block, q) < 1e-6)
        {
            // Hidden faces of the block are never seen.
            EXPECT_LT(q[2], 7.5 - 1e-6) << "the back face";
            EXPECT_LT(q[1], 2.0 - 1e-6) << "the top";
            front += q[2] == 7.0 ? 1 : 0;
        }
    }
    // The front face, 0.5 x 2 m at 5 cm: 200 samples, most below the
    // camera's upper field of view.
    EXPECT_GT(front, 100U);
}

TEST(SurfaceSampler, testsAFramePerStepOfMotion)
{
    const StereoSimulator sim = corridorWithBlock();
    SurfaceSampler::TParameters p;
    p.pose_step = 0.5;
    const auto frames = SurfaceSampler(p).testedFrames(sim, sim.frameCount());
    ASSERT_GE(frames.size(), 2U);
    EXPECT_EQ(frames.front(), 0U);
    // 0.1 m per frame, straight: every fifth frame.
    for (std::size_t k = 1; k < frames.size(); ++k)
    {
        EXPECT_EQ(frames[k] - frames[k - 1], 5U);
    }
}

TEST(SurfaceSampler, refusesBadParameters)
{
    SurfaceSampler::TParameters p;
    p.spacing = 0;
    EXPECT_THROW(SurfaceSampler{p}, std::invalid_argument);
    p = {};
    p.max_range = p.min_range;
    EXPECT_THROW(SurfaceSampler{p}, std::invalid_argument);
}
