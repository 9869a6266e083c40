// SPDX-License-Identifier: BSD-3-Clause
// StereoRenderer: one view (elements culled and binned into image tiles, then
// one RayCaster ray per pixel or sub-pixel), and the stereo pair with exposure
// gain and photometric noise.
#include "RayCaster.h"

#include <emslam/sim/StereoRenderer.h>

#include <mrpt/math/CMatrixFixed.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace emslam::sim
{
using detail::NEAR;
using detail::Prepared;
using detail::RayCaster;

namespace
{
/** Edge [px] of the image tiles over which elements are binned: a ray only
 * tests the elements whose projected bounds overlap its tile. */
constexpr int TILE = 16;
}  // namespace

void StereoRenderer::renderView(
    const World& world,
    const mrpt::poses::CPose3D& T_scene_cam,
    double t,
    cv::Mat& intensity,
    cv::Mat* depth) const
{
    const int W = m_p.width;
    const int H = m_p.height;
    const double f = m_p.focal_px;
    const double cx = m_p.cx >= 0 ? m_p.cx : (W - 1) / 2.0;
    const double cy = m_p.cy >= 0 ? m_p.cy : (H - 1) / 2.0;
    mrpt::math::CMatrixDouble33 Rm;
    T_scene_cam.getRotationMatrix(Rm);
    double R[3][3];
    for (int i = 0; i < 3; ++i)
    {
        for (int j = 0; j < 3; ++j)
        {
            R[i][j] = Rm(i, j);
        }
    }
    const Vec3 o{T_scene_cam.x(), T_scene_cam.y(), T_scene_cam.z()};

    // Elements at time t, and the image rectangle each may cover.
    std::vector<Prepared> els;
    const int tiles_x = (W + TILE - 1) / TILE;
    const int tiles_y = (H + TILE - 1) / TILE;
    std::vector<std::vector<int>> tiles(static_cast<std::size_t>(tiles_x * tiles_y));
    for (const Element& e : world.elements())
    {
        Prepared p{
            e.kind,
            e.axis,
            e.lo,
            e.hi,
            &world.textures()[static_cast<std::size_t>(e.texture)],
            1.0 / e.texel_size,
            e.stretch,
            e.kind == Element::Kind::Box};
        if (e.moving())
        {
            for (std::size_t a = 0; a < 3; ++a)
            {
                p.lo[a] += e.velocity[a] * (t - e.t0);
                p.hi[a] += e.velocity[a] * (t - e.t0);
            }
        }
        // Project the box edges, clipped at the near plane.
        double umin = 1e30;
        double umax = -1e30;
        double vmin = 1e30;
        double vmax = -1e30;
        Vec3 corners[8];
        for (int k = 0; k < 8; ++k)
        {
            const Vec3 w{
                k & 1 ? p.hi[0] : p.lo[0], k & 2 ? p.hi[1] : p.lo[1], k & 4 ? p.hi[2] : p.lo[2]};
            const Vec3 dw{w[0] - o[0], w[1] - o[1], w[2] - o[2]};
            for (std::size_t i = 0; i < 3; ++i)
            {
                corners[k][i] = R[0][i] * dw[0] + R[1][i] * dw[1] + R[2][i] * dw[2];
            }
        }
        auto addPoint = [&](const Vec3& c)
        {
            const double u = cx + f * c[0] / c[2];
            const double v = cy + f * c[1] / c[2];
            umin = std::min(umin, u);
            umax = std::max(umax, u);
            vmin = std::min(vmin, v);
            vmax = std::max(vmax, v);
        };
        for (int a = 0; a < 8; ++a)
        {
            for (int bit = 1; bit < 8; bit <<= 1)
            {
                if ((a & bit) != 0)
                {
                    continue;
                }
                const Vec3& ca = corners[a];
                const Vec3& cb = corners[a | bit];
                const bool ina = ca[2] >= NEAR;
                const bool inb = cb[2] >= NEAR;
                if (ina)
                {
                    addPoint(ca);
                }
                if (inb)
                {
                    addPoint(cb);
                }
                if (ina != inb)
                {
                    const double s = (NEAR - ca[2]) / (cb[2] - ca[2]);
                    addPoint({ca[0] + s * (cb[0] - ca[0]), ca[1] + s * (cb[1] - ca[1]), NEAR});
                }
            }
        }
        if (umin > umax)
        {
            continue;  // entirely behind the camera
        }
        const int tu0 = static_cast<int>(std::floor(std::max(umin - 1.0, 0.0) / TILE));
        const int tu1 = static_cast<int>(std::floor(std::min(umax + 1.0, W - 1.0) / TILE));
        const int tv0 = static_cast<int>(std::floor(std::max(vmin - 1.0, 0.0) / TILE));
        const int tv1 = static_cast<int>(std::floor(std::min(vmax + 1.0, H - 1.0) / TILE));
        if (tu0 > tu1 || tv0 > tv1 || umin > W || vmin > H)
        {
            continue;
        }
        const int idx = static_cast<int>(els.size());
        els.push_back(p);
        for (int ty = tv0; ty <= tv1; ++ty)
        {
            for (int tx = tu0; tx <= tu1; ++tx)
            {
                tiles[static_cast<std::size_t>(ty * tiles_x + tx)].push_back(idx);
            }
        }
    }

    const RayCaster caster(world, std::move(els), o, m_p.max_range, f);
    const int n = m_p.supersampling;
    const float inv_n2 = 1.0F / static_cast<float>(n * n);
    intensity.create(H, W, CV_32F);
    if (depth != nullptr)
    {
        depth->create(H, W, CV_32F);
    }
    auto ray = [&](double u, double v)
    {
        const double xc = (u - cx) / f;
        const double yc = (v - cy) / f;
        return Vec3{
            R[0][0] * xc + R[0][1] * yc + R[0][2], R[1][0] * xc + R[1][1] * yc + R[1][2],
            R[2][0] * xc + R[2][1] * yc + R[2][2]};
    };
    for (int ty = 0; ty < tiles_y; ++ty)
    {
        for (int tx = 0; tx < tiles_x; ++tx)
        {
            const auto& cand = tiles[static_cast<std::size_t>(ty * tiles_x + tx)];
            for (int v = ty * TILE; v < std::min(H, (ty + 1) * TILE); ++v)
            {
                float* row = intensity.ptr<float>(v);
                float* drow = depth != nullptr ? depth->ptr<float>(v) : nullptr;
                for (int u = tx * TILE; u < std::min(W, (tx + 1) * TILE); ++u)
                {
                    double t_hit = 0;
                    if (n == 1)
                    {
                        row[u] = caster.cast(ray(u, v), cand, t_hit);
                        if (drow != nullptr)
                        {
                            drow[u] = static_cast<float>(t_hit);
                        }
                        continue;
                    }
                    float acc = 0;
                    for (int sy = 0; sy < n; ++sy)
                    {
                        for (int sx = 0; sx < n; ++sx)
                        {
                            acc += caster.cast(
                                ray(u + (sx + 0.5) / n - 0.5, v + (sy + 0.5) / n - 0.5), cand,
                                t_hit);
                        }
                    }
                    row[u] = acc * inv_n2;
                    if (drow != nullptr)
                    {
                        caster.cast(ray(u, v), cand, t_hit);
                        drow[u] = static_cast<float>(t_hit);
                    }
                }
            }
        }
    }
}

StereoRenderer::Output StereoRenderer::render(
    const World& world,
    const mrpt::poses::CPose3D& T_scene_left,
    double t,
    double gain,
    std::uint64_t noise_seed,
    bool want_depth) const
{
    Output out;
    const mrpt::poses::CPose3D T_left_right(m_p.baseline, 0, 0, 0, 0, 0);
    cv::Mat views[2];
    renderView(world, T_scene_left, t, views[0], want_depth ? &out.depth : nullptr);
    renderView(world, T_scene_left + T_left_right, t, views[1], nullptr);
    for (int k = 0; k < 2; ++k)
    {
        cv::Mat noisy = views[k] * gain;
        if (m_p.noise_sigma > 0)
        {
            cv::Mat noise(noisy.size(), CV_32F);
            cv::RNG rng(noise_seed * 2 + static_cast<std::uint64_t>(k) + 1);
            rng.fill(noise, cv::RNG::NORMAL, 0.0, m_p.noise_sigma);
            noisy += noise;
        }
        noisy.convertTo(k == 0 ? out.left : out.right, CV_8U);
    }
    return out;
}

}  // namespace emslam::sim
