// SPDX-License-Identifier: BSD-3-Clause
// The fused map at the end of a run (FusedPointCloud::fuse): a 3 m x 2.4 m
// corridor walked range(0) times, 150 views of 6,000 points per walk, depth
// noise along each ray growing with the square of the depth (a stereo
// camera's), 0.1 m voxels, 4 passes along the rays as the mapper runs them.
// Reports the points, the voxels kept and how many points moved.
#include <emslam/slam/FusedPointCloud.h>
#include <emslam/slam/IntensityCloud.h>

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

namespace
{
/** The corridor's views per walk, 0.2 m apart, and points per view. */
constexpr int VIEWS_PER_WALK = 150;
constexpr int POINTS_PER_VIEW = 6000;
/** σ_z = K · z² [m]: 0.2 px of disparity noise at f·b = 40 px·m. */
constexpr double K = 0.2 / 40.0;

using emslam::slam::FusedPointCloud;
using emslam::slam::IntensityCloud;
using mrpt::math::TPoint3D;

struct View
{
    IntensityCloud cloud;  //!< world frame
    TPoint3D origin;
};

/** The views of `walks` walks along z, 0.2 m apart, each a walk's own
 * lateral offset; points on the floor, the ceiling and the walls 0.5-8 m
 * ahead, moved along their ray by the depth noise. */
std::vector<View> corridorViews(int walks)
{
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> noise(0.0, 1.0);
    std::vector<View> views;
    for (int walk = 0; walk < walks; ++walk)
    {
        for (int v = 0; v < VIEWS_PER_WALK; ++v)
        {
            View view;
            view.origin = TPoint3D(0.1 * (walk % 3) - 0.1, 0.05 * (walk % 2), 0.2 * v);
            for (int j = 0; j < POINTS_PER_VIEW; ++j)
            {
                const double z = view.origin.z + 0.5 + 7.5 * u(rng);
                const double across = u(rng);
                TPoint3D truth;
                switch (j % 4)
                {
                    case 0:  // floor
                        truth = TPoint3D(-1.5 + 3.0 * across, 1.2, z);
                        break;
                    case 1:  // ceiling
                        truth = TPoint3D(-1.5 + 3.0 * across, -1.2, z);
                        break;
                    case 2:  // left wall
                        truth = TPoint3D(-1.5, -1.2 + 2.4 * across, z);
                        break;
                    default:  // right wall
                        truth = TPoint3D(1.5, -1.2 + 2.4 * across, z);
                        break;
                }
                const TPoint3D ray = truth - view.origin;
                const double depth = ray.z;
                const double sigma = K * depth * depth;
                const TPoint3D p = truth + ray * (sigma * noise(rng) / ray.norm());
                view.cloud.points.emplace_back(
                    static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
                view.cloud.intensity.push_back(static_cast<std::uint8_t>(j % 256));
                view.cloud.sigma.push_back(static_cast<float>(sigma));
            }
            views.push_back(std::move(view));
        }
    }
    return views;
}

void BM_FuseAlongRays(benchmark::State& state)
{
    const std::vector<View> views = corridorViews(static_cast<int>(state.range(0)));
    FusedPointCloud::TOptions o;
    o.voxel_size = 0.1;
    o.max_sigma = 0.05;
    o.max_observation_sigma = 0.5;
    FusedPointCloud fused(o);
    for (const View& v : views)
    {
        fused.add(v.cloud, v.origin);
    }
    for (auto _ : state)
    {
        fused.fuse();
        benchmark::DoNotOptimize(fused.cloud().size());
    }
    const auto& s = fused.stats();
    state.counters["points"] = static_cast<double>(s.points);
    state.counters["kept_voxels"] = static_cast<double>(s.kept_voxels);
    state.counters["moved_points"] = static_cast<double>(s.moved_points);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.points));
}
}  // namespace

BENCHMARK(BM_FuseAlongRays)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
