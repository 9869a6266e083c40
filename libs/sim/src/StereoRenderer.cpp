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

/** The pinhole camera of one view, in the scene. */
struct ViewGeometry
{
    int W{0}, H{0};
    double f{0}, cx{0}, cy{0};
    double R[3][3]{};  //!< camera axes in the scene (columns)
    Vec3 o{};          //!< camera centre in the scene

    /** The scene direction of the ray through pixel (u, v). */
    Vec3 ray(double u, double v) const
    {
        const double xc = (u - cx) / f;
        const double yc = (v - cy) / f;
        return Vec3{
            R[0][0] * xc + R[0][1] * yc + R[0][2], R[1][0] * xc + R[1][1] * yc + R[1][2],
            R[2][0] * xc + R[2][1] * yc + R[2][2]};
    }
};

/** Image rectangle an element's box may cover (umin > umax: behind the camera). */
struct ImageBounds
{
    double umin{1e30}, umax{-1e30}, vmin{1e30}, vmax{-1e30};
};

/** Projects the box edges of `p`, clipped at the near plane. */
ImageBounds projectBox(const Prepared& p, const ViewGeometry& g)
{
    ImageBounds b;
    Vec3 corners[8];
    for (int k = 0; k < 8; ++k)
    {
        const Vec3 w{
            k & 1 ? p.hi[0] : p.lo[0], k & 2 ? p.hi[1] : p.lo[1], k & 4 ? p.hi[2] : p.lo[2]};
        const Vec3 dw{w[0] - g.o[0], w[1] - g.o[1], w[2] - g.o[2]};
        for (std::size_t i = 0; i < 3; ++i)
        {
            corners[k][i] = g.R[0][i] * dw[0] + g.R[1][i] * dw[1] + g.R[2][i] * dw[2];
        }
    }
    auto addPoint = [&](const Vec3& c)
    {
        const double u = g.cx + g.f * c[0] / c[2];
        const double v = g.cy + g.f * c[1] / c[2];
        b.umin = std::min(b.umin, u);
        b.umax = std::max(b.umax, u);
        b.vmin = std::min(b.vmin, v);
        b.vmax = std::max(b.vmax, v);
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
    return b;
}

/** The world's elements at time t that the view may see, and per image
 * tile (row major, tiles_x per row) the indices of those that may cover it. */
std::vector<Prepared> binElements(
    const World& world,
    const ViewGeometry& g,
    double t,
    int tiles_x,
    std::vector<std::vector<int>>& tiles)
{
    std::vector<Prepared> els;
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
        const ImageBounds b = projectBox(p, g);
        if (b.umin > b.umax)
        {
            continue;  // entirely behind the camera
        }
        const int tu0 = static_cast<int>(std::floor(std::max(b.umin - 1.0, 0.0) / TILE));
        const int tu1 = static_cast<int>(std::floor(std::min(b.umax + 1.0, g.W - 1.0) / TILE));
        const int tv0 = static_cast<int>(std::floor(std::max(b.vmin - 1.0, 0.0) / TILE));
        const int tv1 = static_cast<int>(std::floor(std::min(b.vmax + 1.0, g.H - 1.0) / TILE));
        if (tu0 > tu1 || tv0 > tv1 || b.umin > g.W || b.vmin > g.H)
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
    return els;
}

/** Casts the rays of one tile's pixels (n x n per pixel, the depth from
 * the pixel's centre) against the tile's candidate elements. */
void renderTile(
    const RayCaster& caster,
    const ViewGeometry& g,
    int n,
    int tx,
    int ty,
    const std::vector<int>& cand,
    cv::Mat& intensity,
    cv::Mat* depth)
{
    const float inv_n2 = 1.0F / static_cast<float>(n * n);
    for (int v = ty * TILE; v < std::min(g.H, (ty + 1) * TILE); ++v)
    {
        float* row = intensity.ptr<float>(v);
        float* drow = depth != nullptr ? depth->ptr<float>(v) : nullptr;
        for (int u = tx * TILE; u < std::min(g.W, (tx + 1) * TILE); ++u)
        {
            double t_hit = 0;
            if (n == 1)
            {
                row[u] = caster.cast(g.ray(u, v), cand, t_hit);
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
                        g.ray(u + (sx + 0.5) / n - 0.5, v + (sy + 0.5) / n - 0.5), cand, t_hit);
                }
            }
            row[u] = acc * inv_n2;
            if (drow != nullptr)
            {
                caster.cast(g.ray(u, v), cand, t_hit);
                drow[u] = static_cast<float>(t_hit);
            }
        }
    }
}
}  // namespace

void StereoRenderer::renderView(
    const World& world,
    const mrpt::poses::CPose3D& T_scene_cam,
    double t,
    cv::Mat& intensity,
    cv::Mat* depth) const
{
    ViewGeometry g;
    g.W = m_p.width;
    g.H = m_p.height;
    g.f = m_p.focal_px;
    g.cx = m_p.cx >= 0 ? m_p.cx : (g.W - 1) / 2.0;
    g.cy = m_p.cy >= 0 ? m_p.cy : (g.H - 1) / 2.0;
    mrpt::math::CMatrixDouble33 Rm;
    T_scene_cam.getRotationMatrix(Rm);
    for (int i = 0; i < 3; ++i)
    {
        for (int j = 0; j < 3; ++j)
        {
            g.R[i][j] = Rm(i, j);
        }
    }
    g.o = Vec3{T_scene_cam.x(), T_scene_cam.y(), T_scene_cam.z()};

    // Elements at time t, and the image rectangle each may cover.
    const int tiles_x = (g.W + TILE - 1) / TILE;
    const int tiles_y = (g.H + TILE - 1) / TILE;
    std::vector<std::vector<int>> tiles(static_cast<std::size_t>(tiles_x * tiles_y));
    std::vector<Prepared> els = binElements(world, g, t, tiles_x, tiles);

    const RayCaster caster(world, std::move(els), g.o, m_p.max_range, g.f);
    intensity.create(g.H, g.W, CV_32F);
    if (depth != nullptr)
    {
        depth->create(g.H, g.W, CV_32F);
    }
    for (int ty = 0; ty < tiles_y; ++ty)
    {
        for (int tx = 0; tx < tiles_x; ++tx)
        {
            renderTile(
                caster, g, m_p.supersampling, tx, ty,
                tiles[static_cast<std::size_t>(ty * tiles_x + tx)], intensity, depth);
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
