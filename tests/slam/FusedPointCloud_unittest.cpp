// SPDX-License-Identifier: BSD-3-Clause
// Fusing the map's points by their depth uncertainty: synthetic views of known
// surfaces with known noise; the fused error shrinks as 1/sqrt(sum 1/sigma^2)
// predicts, gating drops the uncertain points, and the fusion along the rays
// gathers a surface's spread back onto it.
#include <emslam/slam/FusedPointCloud.h>
#include <emslam/slam/IntensityCloud.h>

#include <mrpt/math/TPoint3D.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

using emslam::slam::FusedPointCloud;
using emslam::slam::IntensityCloud;
using mrpt::math::TPoint3D;

namespace
{
/** A point `truth` seen from `origin` with depth noise `sigma` along the ray. */
void addNoisyPoint(
    IntensityCloud& c,
    const TPoint3D& origin,
    const TPoint3D& truth,
    double sigma,
    std::mt19937& rng)
{
    std::normal_distribution<double> n(0.0, sigma);
    const TPoint3D d = truth - origin;
    const double r = d.norm();
    const double e = n(rng);
    const TPoint3D p = truth + d * (e / r);
    c.points.emplace_back(
        static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
    c.intensity.push_back(100);
    c.sigma.push_back(static_cast<float>(sigma));
}

/** One view of `truth` from `origin`: a single point. */
IntensityCloud onePoint(
    const TPoint3D& origin, const TPoint3D& truth, double sigma, std::mt19937& rng)
{
    IntensityCloud c;
    addNoisyPoint(c, origin, truth, sigma, rng);
    return c;
}

/** The wall z = `wall_z`, x in [-1, 1], y in [-0.5, 0.5], on a 0.1 m grid
 * of cell centres, seen from `origin` with depth noise k·depth². */
IntensityCloud wallView(const TPoint3D& origin, double wall_z, double k, std::mt19937& rng)
{
    IntensityCloud c;
    for (int i = 0; i < 20; ++i)
    {
        for (int j = 0; j < 10; ++j)
        {
            const TPoint3D truth(-0.95 + 0.1 * i, -0.45 + 0.1 * j, wall_z);
            const double depth = wall_z - origin.z;
            addNoisyPoint(c, origin, truth, k * depth * depth, rng);
        }
    }
    return c;
}

/** Distances of the fused points to the wall z = wall_z. */
std::vector<double> wallErrors(const IntensityCloud& c, double wall_z)
{
    std::vector<double> e;
    for (const auto& p : c.points)
    {
        e.push_back(std::abs(p.z - wall_z));
    }
    std::sort(e.begin(), e.end());
    return e;
}

/** 0.1 m voxels, kept up to a fused sigma of 0.05 m. */
FusedPointCloud::TOptions decimetreVoxels()
{
    FusedPointCloud::TOptions o;
    o.voxel_size = 0.1;
    o.max_sigma = 0.05;
    return o;
}

double median(const std::vector<double>& sorted)
{
    return sorted.empty() ? NAN : sorted[sorted.size() / 2];
}
}  // namespace

TEST(FusedPointCloud, errorShrinksAsPredictedWithTheViews)
{
    // One true point in the middle of a 1 m voxel, n views of sigma 0.05 m
    // from around it: the fused error's RMS over many trials is sigma/sqrt(n),
    // as the fused sigma says.
    const double sigma = 0.05;
    const TPoint3D truth(0.5, 0.5, 4.5);
    FusedPointCloud::TOptions o;
    o.voxel_size = 1.0;
    o.along_rays = false;
    std::mt19937 rng(7);
    for (const int n : {1, 4, 16, 64})
    {
        double sum_sq = 0.0;
        const int trials = 400;
        for (int t = 0; t < trials; ++t)
        {
            FusedPointCloud f(o);
            for (int v = 0; v < n; ++v)
            {
                const double a = 0.3 * v;
                f.add(
                    onePoint({std::cos(a), 0.2 * std::sin(a), 0.0}, truth, sigma, rng),
                    {std::cos(a), 0.2 * std::sin(a), 0.0});
            }
            f.fuse();
            ASSERT_EQ(f.cloud().size(), 1u);
            EXPECT_NEAR(f.cloud().sigma[0], sigma / std::sqrt(n), 1e-6);
            const auto& p = f.cloud().points[0];
            sum_sq += (TPoint3D(p) - truth).sqrNorm();
        }
        const double rms = std::sqrt(sum_sq / trials);
        // 400 trials: the RMS is within ~7 % of its expectation (1 sigma).
        EXPECT_NEAR(rms, sigma / std::sqrt(n), 0.2 * sigma / std::sqrt(n)) << n << " views";
    }
}

TEST(FusedPointCloud, weighsEachViewByItsInverseVariance)
{
    // One precise view (1 cm) and nine imprecise ones (10 cm): the fused
    // sigma is 1/sqrt(1/0.01^2 + 9/0.1^2), and the error stays near the
    // precise view's, far below the plain mean's.
    const TPoint3D truth(0.5, 0.5, 3.5);
    const double expected = 1.0 / std::sqrt(1.0 / (0.01 * 0.01) + 9.0 / (0.1 * 0.1));
    FusedPointCloud::TOptions o;
    o.voxel_size = 1.0;
    o.along_rays = false;
    std::mt19937 rng(11);
    double sum_sq = 0.0, plain_sq = 0.0;
    const int trials = 400;
    for (int t = 0; t < trials; ++t)
    {
        FusedPointCloud f(o);
        TPoint3D plain(0, 0, 0);
        for (int v = 0; v < 10; ++v)
        {
            const TPoint3D origin(0.1 * v, 0.0, 0.0);
            const IntensityCloud c = onePoint(origin, truth, v == 0 ? 0.01 : 0.1, rng);
            plain = plain + TPoint3D(c.points[0]) * 0.1;
            f.add(c, origin);
        }
        f.fuse();
        ASSERT_EQ(f.cloud().size(), 1u);
        EXPECT_NEAR(f.cloud().sigma[0], expected, 1e-6);
        sum_sq += (TPoint3D(f.cloud().points[0]) - truth).sqrNorm();
        plain_sq += (plain - truth).sqrNorm();
    }
    EXPECT_NEAR(std::sqrt(sum_sq / trials), expected, 0.2 * expected);
    EXPECT_GT(std::sqrt(plain_sq / trials), 2.5 * expected);
}

TEST(FusedPointCloud, gatingDropsTheUncertainPoints)
{
    // A near wall (2 m: sigma 0.02 m) and a far one (8 m: sigma 0.32 m) seen
    // once each, sigma = 0.005 z^2: with max_sigma 0.05 m only the near one is
    // kept; points above max_observation_sigma are not even fused.
    std::mt19937 rng(3);
    const TPoint3D origin(0, 0, 0);
    FusedPointCloud::TOptions o;
    o.voxel_size = 0.1;
    o.max_sigma = 0.05;
    o.along_rays = false;
    FusedPointCloud f(o);
    const std::size_t near_first = f.add(wallView(origin, 2.05, 0.005, rng), origin);
    const std::size_t far_first = f.add(wallView(origin, 8.05, 0.005, rng), origin);
    f.fuse();
    for (std::size_t i = near_first; i < far_first; ++i)
    {
        EXPECT_GE(f.fusedIndexOf(i), 0);
    }
    for (std::size_t i = far_first; i < f.pointCount(); ++i)
    {
        EXPECT_EQ(f.fusedIndexOf(i), -1);
    }
    for (const auto& p : f.cloud().points)
    {
        EXPECT_LT(p.z, 3.0);
    }
    for (const float s : f.cloud().sigma)
    {
        EXPECT_LE(s, 0.05f);
    }
    EXPECT_EQ(f.stats().used_points, 400u);

    // The far wall seen 100 times fuses below the gate (0.32 / 10 = 0.032 m)
    // once its points are gathered along their rays (per voxel alone, each
    // of the ~7 voxels its spread covers holds too few).
    o.along_rays = true;
    FusedPointCloud many(o);
    for (int v = 0; v < 100; ++v)
    {
        const TPoint3D from(0.01 * v, 0.0, 0.0);
        many.add(wallView(from, 8.05, 0.005, rng), from);
    }
    many.fuse();
    EXPECT_GT(many.cloud().size(), 100u);

    // ... unless each view is above max_observation_sigma.
    o.max_observation_sigma = 0.3;
    FusedPointCloud refused(o);
    for (int v = 0; v < 100; ++v)
    {
        const TPoint3D from(0.01 * v, 0.0, 0.0);
        refused.add(wallView(from, 8.05, 0.005, rng), from);
    }
    refused.fuse();
    EXPECT_EQ(refused.stats().used_points, 0u);
    EXPECT_EQ(refused.cloud().size(), 0u);
}

TEST(FusedPointCloud, alongTheRaysGathersASurfaceSpreadOverVoxels)
{
    // A wall 4 m away seen 40 times with sigma 0.15 m: its points spread over
    // ±3 voxels of 0.1 m in depth. Per voxel alone the fused points keep that
    // spread; along the rays they gather on the wall, and the fused point of
    // each voxel is the mean of the spread, near the truth.
    const double wall_z = 4.05, k = 0.15 / 16.0;
    FusedPointCloud::TOptions voxels_only;
    voxels_only.voxel_size = 0.1;
    voxels_only.max_sigma = 0.05;
    voxels_only.along_rays = false;
    FusedPointCloud::TOptions rays = voxels_only;
    rays.along_rays = true;
    FusedPointCloud a(voxels_only), b(rays);
    std::mt19937 rng(5);
    for (int v = 0; v < 40; ++v)
    {
        const TPoint3D from(0.02 * (v % 7) - 0.06, 0.01 * (v % 5), 0.0);
        const IntensityCloud c = wallView(from, wall_z, k, rng);
        a.add(c, from);
        b.add(c, from);
    }
    a.fuse();
    b.fuse();
    const auto ea = wallErrors(a.cloud(), wall_z);
    const auto eb = wallErrors(b.cloud(), wall_z);
    // Per voxel: the voxels 0.1 m off the wall hold enough points to pass
    // the gate, at the mean of their side of the spread (measured: median
    // 0.078 m, p90 0.10 m).
    ASSERT_FALSE(ea.empty());
    EXPECT_GT(median(ea), 0.06);
    // Along the rays: one voxel deep (200 wall cells); the mean of 40 views
    // of 0.15 m is 0.024 m off, less where neighbours join (measured: median
    // 0.017 m, p90 0.047 m, 203 points).
    ASSERT_FALSE(eb.empty());
    EXPECT_LT(median(eb), 0.03);
    EXPECT_LT(eb[eb.size() * 9 / 10], 0.06);
    EXPECT_LE(b.cloud().size(), 220u);
    EXPECT_GE(b.cloud().size(), 180u);
    EXPECT_GT(b.stats().moved_points, 4000u);
}

TEST(FusedPointCloud, aPreciseViewGathersTheImpreciseOnes)
{
    // One view from 1 m (sigma 0.005 m) and 30 from 6 m (sigma 0.18 m): along
    // the rays the far points join the near view's voxels, and the map has
    // the wall where the near view put it, with no ghost layers.
    const double wall_z = 6.05, k = 0.005;
    FusedPointCloud f(decimetreVoxels());
    std::mt19937 rng(9);
    const TPoint3D near_view(0, 0, wall_z - 1.0);
    f.add(wallView(near_view, wall_z, k, rng), near_view);
    for (int v = 0; v < 30; ++v)
    {
        const TPoint3D from(0.03 * (v % 5), 0.02 * (v % 3), 0.0);
        f.add(wallView(from, wall_z, k, rng), from);
    }
    f.fuse();
    const auto e = wallErrors(f.cloud(), wall_z);
    ASSERT_FALSE(e.empty());
    EXPECT_LT(e.back(), 0.06);
    EXPECT_LE(f.cloud().size(), 220u);
    EXPECT_GE(f.cloud().size(), 180u);
}

TEST(FusedPointCloud, aVeryUncertainPointJoinsTheSurfaceOnItsRay)
{
    // A wall seen precisely from 1 m, and two lone points whose rays cross
    // it, measured 1 m and 3 m in front of it with sigma 1.5 m and 8 m: both
    // searches reach the wall (±2 sigma), the second one beyond the 126
    // samples a side that the search records, so it searches its ray again
    // in each pass. Both join the wall's voxels.
    const double wall_z = 6.05;
    FusedPointCloud f(decimetreVoxels());
    std::mt19937 rng(3);
    const TPoint3D near_view(0, 0, wall_z - 1.0);
    f.add(wallView(near_view, wall_z, 0.005, rng), near_view);
    const TPoint3D far_view(0.1, 0.05, 0.0);
    std::vector<std::size_t> lone;
    for (const auto& [in_front, sigma] : {std::pair{1.0, 1.5}, std::pair{3.0, 8.0}})
    {
        // On the ray from far_view through the wall cell (0.05, 0.05).
        const TPoint3D on_wall(0.05, 0.05, wall_z);
        const TPoint3D d = on_wall - far_view;
        const TPoint3D p = on_wall - d * (in_front / d.norm());
        IntensityCloud c;
        c.points.emplace_back(
            static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
        c.intensity.push_back(50);
        c.sigma.push_back(static_cast<float>(sigma));
        lone.push_back(f.add(c, far_view));
    }
    f.fuse();
    EXPECT_EQ(f.stats().used_points, 202u);
    for (const std::size_t i : lone)
    {
        const std::int32_t fused = f.fusedIndexOf(i);
        ASSERT_GE(fused, 0) << "point " << i;
        EXPECT_NEAR(f.cloud().points[static_cast<std::size_t>(fused)].z, wall_z, 0.06);
    }
    EXPECT_EQ(f.stats().moved_points, 2u);
}

TEST(FusedPointCloud, refusesBadOptions)
{
    FusedPointCloud::TOptions o;
    o.voxel_size = 0.0;
    EXPECT_THROW(FusedPointCloud{o}, std::invalid_argument);
    o.voxel_size = 0.1;
    o.max_sigma = 0.0;
    EXPECT_THROW(FusedPointCloud{o}, std::invalid_argument);
}
