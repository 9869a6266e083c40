// SPDX-License-Identifier: BSD-3-Clause
// World generators for type = ground (flat floor and boxes) and type = terrain
// (height field, rocks and bushes): random placement kept off the trajectory.
#include "WorldDetail.h"

#include <emslam/sim/World.h>

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

namespace emslam::sim
{
using detail::makeBox;
using detail::makePlane;
using detail::mix;

namespace
{
/** Distance from (x, z) to the polyline through `pts`. */
double distanceToPath(double x, double z, const std::vector<std::array<double, 2>>& pts)
{
    double best = 1e30;
    for (std::size_t i = 0; i < pts.size(); ++i)
    {
        const auto& a = pts[i];
        const auto& b = pts[std::min(i + 1, pts.size() - 1)];
        const double dx = b[0] - a[0];
        const double dz = b[1] - a[1];
        const double l2 = dx * dx + dz * dz;
        double t = l2 > 0 ? ((x - a[0]) * dx + (z - a[1]) * dz) / l2 : 0.0;
        t = std::clamp(t, 0.0, 1.0);
        best = std::min(best, std::hypot(x - a[0] - t * dx, z - a[1] - t * dz));
    }
    return best;
}
}  // namespace

void World::buildGround(
    const mrpt::config::CConfigFileBase&,
    std::uint64_t seed,
    const std::vector<std::array<double, 2>>& keep_out)
{
    const auto& p = ground;
    const double h = p.extent / 2;
    const int gt = addTexture(ProceduralTexture::generate(p.ground_texture, mix(seed, 1), 512));
    addElement(makePlane(1, {-h, 0, -h}, {h, 0, h}, gt, p.texel_size));
    std::vector<int> obj_tex;
    for (int i = 0; i < 4; ++i)
    {
        obj_tex.push_back(
            addTexture(ProceduralTexture::generate(p.object_texture, mix(seed, 10 + i), 256)));
    }
    std::mt19937_64 rng(mix(seed, 2));
    std::uniform_real_distribution<double> pos(-0.95 * h, 0.95 * h);
    std::uniform_real_distribution<double> size(p.min_size, p.max_size);
    int placed = 0;
    for (int tries = 0; placed < p.objects && tries < 50 * (p.objects + 1); ++tries)
    {
        const double x = pos(rng);
        const double z = pos(rng);
        const double sx = size(rng);
        const double sz = size(rng);
        const double sy = size(rng);
        if (!keep_out.empty() &&
            distanceToPath(x, z, keep_out) < p.clearance + 0.5 * std::hypot(sx, sz))
        {
            continue;
        }
        addElement(makeBox(
            {x - sx / 2, 0, z - sz / 2}, {x + sx / 2, sy, z + sz / 2},
            obj_tex[static_cast<std::size_t>(placed) % obj_tex.size()], p.texel_size));
        ++placed;
    }
}

void World::buildTerrain(
    const mrpt::config::CConfigFileBase&,
    std::uint64_t seed,
    const std::vector<std::array<double, 2>>& keep_out)
{
    const auto& p = terrain;
    const int n = static_cast<int>(std::ceil(p.extent / p.cell)) + 1;
    HeightField hf;
    hf.cell = p.cell;
    hf.x0 = -p.extent / 2;
    hf.z0 = -p.extent / 2;
    // Relief: multi-scale noise, normalized to the requested amplitude.
    const ProceduralTexture relief = ProceduralTexture::generate("noise", mix(seed, 3), 256);
    cv::Mat h;
    cv::resize(relief.image(), h, cv::Size(n, n), 0, 0, cv::INTER_CUBIC);
    cv::Scalar mean;
    cv::Scalar stddev;
    cv::meanStdDev(h, mean, stddev);
    h = (h - mean[0]) * (p.amplitude / std::max(stddev[0], 1e-6));
    std::mt19937_64 rng(mix(seed, 4));
    std::uniform_real_distribution<double> pos(-0.45 * p.extent, 0.45 * p.extent);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    struct Bump
    {
        double x, z, r, a;
    };
    std::vector<Bump> bumps;
    for (int tries = 0; static_cast<int>(bumps.size()) < p.rocks && tries < 50 * (p.rocks + 1);
         ++tries)
    {
        const Bump b{pos(rng), pos(rng), 0.2 + 0.5 * u01(rng), 0.1 + 0.4 * u01(rng)};
        if (!keep_out.empty() && distanceToPath(b.x, b.z, keep_out) < p.clearance + 2 * b.r)
        {
            continue;
        }
        bumps.push_back(b);
    }
    for (int iz = 0; iz < n; ++iz)
    {
        const double z = hf.z0 + iz * p.cell;
        const double centre = 3.0 * std::sin(z / 7.0);
        for (int ix = 0; ix < n; ++ix)
        {
            const double x = hf.x0 + ix * p.cell;
            const double d = (x - centre) / (0.5 * p.channel_width);
            double v = h.at<float>(iz, ix) - p.channel_depth * std::exp(-d * d);
            for (const auto& b : bumps)
            {
                const double r2 = ((x - b.x) * (x - b.x) + (z - b.z) * (z - b.z)) / (b.r * b.r);
                if (r2 < 9)
                {
                    v += b.a * std::exp(-r2);
                }
            }
            h.at<float>(iz, ix) = static_cast<float>(v);
        }
    }
    hf.heights = h;
    double mn = 0;
    double mx = 0;
    cv::minMaxLoc(h, &mn, &mx);
    hf.min_height = static_cast<float>(mn);
    hf.max_height = static_cast<float>(mx);
    // Slope bound and Lambert shading (light from above and the side).
    cv::Mat gx;
    cv::Mat gz;
    cv::Sobel(h, gx, CV_32F, 1, 0, 1, 0.5 / p.cell);
    cv::Sobel(h, gz, CV_32F, 0, 1, 1, 0.5 / p.cell);
    double sx = 0;
    double sz = 0;
    cv::minMaxLoc(cv::abs(gx), nullptr, &sx);
    cv::minMaxLoc(cv::abs(gz), nullptr, &sz);
    hf.max_slope = std::max({sx, sz, 0.05});
    hf.shade.create(n, n, CV_32F);
    const double lx = 0.5;
    const double ly = 0.8;
    const double lz = 0.33;
    for (int iz = 0; iz < n; ++iz)
    {
        for (int ix = 0; ix < n; ++ix)
        {
            const double ax = -gx.at<float>(iz, ix);
            const double az = -gz.at<float>(iz, ix);
            const double norm = std::sqrt(ax * ax + 1 + az * az);
            const double lam =
                (ax * lx + ly + az * lz) / norm / std::sqrt(lx * lx + ly * ly + lz * lz);
            hf.shade.at<float>(iz, ix) = static_cast<float>(0.35 + 0.65 * std::max(0.0, lam));
        }
    }
    const int gt = addTexture(ProceduralTexture::generate(p.ground_texture, mix(seed, 5), 512));
    setHeightField(hf, gt, p.texel_size);
    // Bushes: boxes standing on the relief.
    const int bush_tex = addTexture(ProceduralTexture::generate("bush", mix(seed, 6), 256));
    int placed = 0;
    for (int tries = 0; placed < p.bushes && tries < 50 * (p.bushes + 1); ++tries)
    {
        const double x = pos(rng);
        const double z = pos(rng);
        const double s = 0.4 + 0.8 * u01(rng);
        const double t = 0.3 + 0.7 * u01(rng);
        if (!keep_out.empty() && distanceToPath(x, z, keep_out) < p.clearance + s)
        {
            continue;
        }
        const double g = m_height.at(x, z);
        addElement(makeBox(
            {x - s / 2, g - 0.1, z - s / 2}, {x + s / 2, g + t, z + s / 2}, bush_tex, 0.01));
        ++placed;
    }
}

}  // namespace emslam::sim
