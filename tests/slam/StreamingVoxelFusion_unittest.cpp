// SPDX-License-Identifier: BSD-3-Clause
// The live view's fusion: a voxel is handed out once, when enough views have
// brought its fused sigma down to the gate, at the weighted mean of its points.
#include <emslam/slam/StreamingVoxelFusion.h>

#include <mrpt/poses/CPose3D.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using emslam::slam::IntensityCloud;
using emslam::slam::StreamingVoxelFusion;

namespace
{
/** One point 0.05 m inside a voxel, at `z` in the camera frame, sigma `s`. */
IntensityCloud onePoint(double z, double s, std::uint8_t grey)
{
    IntensityCloud c;
    c.points.emplace_back(0.05f, 0.05f, static_cast<float>(z));
    c.intensity.push_back(grey);
    c.sigma.push_back(static_cast<float>(s));
    return c;
}
}  // namespace

TEST(StreamingVoxelFusion, handsAVoxelOutOnceItsFusedSigmaReachesTheGate)
{
    // sigma 0.099 m per view, gate 0.05 m: the 4th view gives 0.0495 m.
    StreamingVoxelFusion f(0.1, 0.05, 0.5);
    const mrpt::poses::CPose3D at_origin;
    for (int v = 0; v < 3; ++v)
    {
        EXPECT_TRUE(f.add(onePoint(4.05 + 0.01 * v, 0.099, 100), at_origin).empty()) << v;
    }
    const IntensityCloud out = f.add(onePoint(4.08, 0.099, 140), at_origin);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out.points[0].z, (4.05 + 4.06 + 4.07 + 4.08) / 4, 1e-5);
    EXPECT_NEAR(out.sigma[0], 0.0495, 1e-6);
    EXPECT_EQ(out.intensity[0], 110);
    // Handed out once: more views add nothing.
    EXPECT_TRUE(f.add(onePoint(4.05, 0.1, 100), at_origin).empty());
    EXPECT_EQ(f.voxelCount(), 1u);
}

TEST(StreamingVoxelFusion, placesViewsAtTheirPosesAndSkipsUncertainPoints)
{
    StreamingVoxelFusion f(0.1, 0.05, 0.5);
    // A precise point is out at once, at its world position.
    const IntensityCloud out =
        f.add(onePoint(1.0, 0.01, 50), mrpt::poses::CPose3D(2, 0, 0, 0, 0, 0));
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out.points[0].x, 2.05, 1e-5);
    EXPECT_NEAR(out.points[0].z, 1.0, 1e-5);
    // Points above max_observation_sigma are not used at all.
    for (int v = 0; v < 1000; ++v)
    {
        EXPECT_TRUE(f.add(onePoint(9.0, 0.6, 50), mrpt::poses::CPose3D()).empty());
    }
    EXPECT_EQ(f.voxelCount(), 1u);
    EXPECT_THROW(StreamingVoxelFusion(0.0, 0.05, 0.5), std::invalid_argument);
}
