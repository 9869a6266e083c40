// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/sim/StereoRenderer.h>

#include <mrpt/math/CMatrixFixed.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace emslam::sim
{
namespace
{
constexpr const char* SECTION = "Camera";
constexpr int TILE = 16;
constexpr double NEAR = 0.01;
constexpr float SKY = 205.0F;

[[noreturn]] void bad(const std::string& key, const std::string& msg)
{
    throw std::invalid_argument(std::string("[") + SECTION + "] " + key + ": " + msg);
}

/** An element ready for ray casting at one time instant. */
struct Prepared
{
    Element::Kind kind;
    int axis;
    Vec3 lo, hi;
    const ProceduralTexture* tex;
    double inv_texel;
    bool stretch;
    bool box_local;  // texture coordinates relative to lo (boxes move with their texture)
};

float bilinear(const cv::Mat& m, double fx, double fz)
{
    fx = std::clamp(fx, 0.0, m.cols - 1.001);
    fz = std::clamp(fz, 0.0, m.rows - 1.001);
    const int ix = static_cast<int>(fx);
    const int iz = static_cast<int>(fz);
    const auto ax = static_cast<float>(fx - ix);
    const auto az = static_cast<float>(fz - iz);
    const float* r0 = m.ptr<float>(iz);
    const float* r1 = m.ptr<float>(iz + 1);
    return (r0[ix] * (1 - ax) + r0[ix + 1] * ax) * (1 - az) +
           (r1[ix] * (1 - ax) + r1[ix + 1] * ax) * az;
}

/** Ray caster for one view. */
class Caster
{
public:
    Caster(const World& w, std::vector<Prepared> els, const Vec3& o, double max_range, double focal)
        : m_world(w), m_els(std::move(els)), m_o(o), m_max(max_range), m_inv_f(1.0 / focal)
    {
    }

    /** Closest hit along o + t d (t: camera depth since d_cam.z == 1); returns
     * the intensity, and t (0: nothing). */
    float cast(const Vec3& d, const std::vector<int>& cand, double& t_hit) const
    {
        double best = m_max;
        int best_e = -1;
        int best_axis = 0;
        int field = -1;
        for (int idx : cand)
        {
            const Prepared& e = m_els[static_cast<std::size_t>(idx)];
            if (e.kind == Element::Kind::HeightField)
            {
                field = idx;  // marched last, up to the nearest other hit
                continue;
            }
            if (e.kind == Element::Kind::Plane)
            {
                const auto a = static_cast<std::size_t>(e.axis);
                if (d[a] == 0.0)
                {
                    continue;
                }
                const double t = (e.lo[a] - m_o[a]) / d[a];
                if (t <= NEAR || t >= best)
                {
                    continue;
                }
                bool inside = true;
                for (std::size_t b = 0; b < 3 && inside; ++b)
                {
                    if (b != a)
                    {
                        const double q = m_o[b] + t * d[b];
                        inside = q >= e.lo[b] && q <= e.hi[b];
                    }
                }
                if (inside)
                {
                    best = t;
                    best_e = idx;
                    best_axis = e.axis;
                }
            }
            else if (e.kind == Element::Kind::Box)
            {
                double tmin = -std::numeric_limits<double>::infinity();
                double tmax = std::numeric_limits<double>::infinity();
                int ax = 0;
                bool miss = false;
                for (std::size_t a = 0; a < 3; ++a)
                {
                    if (d[a] == 0.0)
                    {
                        if (m_o[a] < e.lo[a] || m_o[a] > e.hi[a])
                        {
                            miss = true;
                            break;
                        }
                        continue;
                    }
                    const double inv = 1.0 / d[a];
                    double t1 = (e.lo[a] - m_o[a]) * inv;
                    double t2 = (e.hi[a] - m_o[a]) * inv;
                    if (t1 > t2)
                    {
                        std::swap(t1, t2);
                    }
                    if (t1 > tmin)
                    {
                        tmin = t1;
                        ax = static_cast<int>(a);
                    }
                    tmax = std::min(tmax, t2);
                }
                if (miss || tmin > tmax || tmin <= NEAR || tmin >= best)
                {
                    continue;
                }
                best = tmin;
                best_e = idx;
                best_axis = ax;
            }
        }
        if (field >= 0)
        {
            const double t = castHeightField(m_els[static_cast<std::size_t>(field)], d, best);
            if (t > 0 && t < best)
            {
                best = t;
                best_e = field;
                best_axis = 1;
            }
        }
        if (best_e < 0)
        {
            t_hit = 0;
            return SKY;
        }
        t_hit = best;
        return shade(m_els[static_cast<std::size_t>(best_e)], best_axis, d, best);
    }

private:
    double castHeightField(const Prepared& e, const Vec3& d, double t_limit) const
    {
        // Clip the ray to the field's bounding box.
        double ta = NEAR;
        double tb = t_limit;
        for (std::size_t a = 0; a < 3; ++a)
        {
            if (d[a] == 0.0)
            {
                if (m_o[a] < e.lo[a] || m_o[a] > e.hi[a])
                {
                    return -1;
                }
                continue;
            }
            double t1 = (e.lo[a] - m_o[a]) / d[a];
            double t2 = (e.hi[a] - m_o[a]) / d[a];
            if (t1 > t2)
            {
                std::swap(t1, t2);
            }
            ta = std::max(ta, t1);
            tb = std::min(tb, t2);
        }
        if (ta >= tb)
        {
            return -1;
        }
        const HeightField& hf = m_world.heightField();
        const double dxz = std::sqrt(d[0] * d[0] + d[2] * d[2]);
        const double denom = hf.max_slope * dxz + std::abs(d[1]);
        const double dn = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        // HeightField::at() with multiplications instead of divisions (hot loop).
        const double inv_cell = 1.0 / hf.cell;
        const double fx_max = hf.heights.cols - 1.001;
        const double fz_max = hf.heights.rows - 1.001;
        auto f = [&](double t)
        {
            const double fx = std::clamp((m_o[0] + t * d[0] - hf.x0) * inv_cell, 0.0, fx_max);
            const double fz = std::clamp((m_o[2] + t * d[2] - hf.z0) * inv_cell, 0.0, fz_max);
            const int ix = static_cast<int>(fx);
            const int iz = static_cast<int>(fz);
            const double ax = fx - ix;
            const double az = fz - iz;
            const float* r0 = hf.heights.ptr<float>(iz) + ix;
            const float* r1 = hf.heights.ptr<float>(iz + 1) + ix;
            const double h =
                (r0[0] * (1 - ax) + r0[1] * ax) * (1 - az) + (r1[0] * (1 - ax) + r1[1] * ax) * az;
            return m_o[1] + t * d[1] - h;
        };
        double t = ta;
        double ft = f(t);
        if (ft <= 0)
        {
            return -1;  // starts under the ground
        }
        // Exit t of the ray from grid cell (ix, iz) of edge size.
        auto cellExit = [&](double size, int ix, int iz)
        {
            double t_exit = tb;
            if (d[0] != 0.0)
            {
                const double xe = hf.x0 + (d[0] > 0 ? ix + 1 : ix) * size;
                t_exit = std::min(t_exit, (xe - m_o[0]) / d[0]);
            }
            if (d[2] != 0.0)
            {
                const double ze = hf.z0 + (d[2] > 0 ? iz + 1 : iz) * size;
                t_exit = std::min(t_exit, (ze - m_o[2]) / d[2]);
            }
            return t_exit;
        };
        const double bsize = hf.cell * HeightField::BLOCK;
        const double inv_bsize = 1.0 / bsize;
        const double csize = bsize * HeightField::COARSE;
        const int nbx = hf.block_max.cols;
        const int nbz = hf.block_max.rows;
        const int ncx = hf.coarse_max.cols;
        const int ncz = hf.coarse_max.rows;
        for (int it = 0; it < 1000 && t < tb; ++it)
        {
            // Empty-space skipping (coarse cells, then blocks): if the ray stays
            // above a cell's highest sample until it leaves the cell, jump to the
            // cell's exit; if it sinks below it inside, jump to where it does.
            const double x = m_o[0] + t * d[0];
            const double z = m_o[2] + t * d[2];
            const double y = m_o[1] + t * d[1];
            const int bx = std::clamp(static_cast<int>((x - hf.x0) * inv_bsize), 0, nbx - 1);
            const int bz = std::clamp(static_cast<int>((z - hf.z0) * inv_bsize), 0, nbz - 1);
            double cmax = hf.block_max.at<float>(bz, bx);
            if (y > cmax)
            {
                double t_exit = tb;
                const int cx = std::min(bx / HeightField::COARSE, ncx - 1);
                const int cz = std::min(bz / HeightField::COARSE, ncz - 1);
                const double c_max = hf.coarse_max.at<float>(cz, cx);
                bool coarse = false;
                if (y > c_max)
                {
                    t_exit = cellExit(csize, cx, cz);
                    coarse = d[1] >= 0 || m_o[1] + t_exit * d[1] > c_max;
                    cmax = c_max;
                }
                if (!coarse)
                {
                    t_exit = cellExit(bsize, bx, bz);
                    cmax = hf.block_max.at<float>(bz, bx);
                }
                if (t_exit > t)
                {
                    if (d[1] >= 0 || m_o[1] + t_exit * d[1] > cmax)
                    {
                        t = t_exit + 1e-6;
                        if (t >= tb)
                        {
                            break;
                        }
                        ft = f(t);
                        continue;
                    }
                    // No crossing before the ray sinks below the cell's maximum.
                    t = (cmax - m_o[1]) / d[1];
                    ft = f(t);
                }
            }
            const double step = std::max(0.8 * ft / denom, (0.05 + 0.012 * t) / dn);
            const double tn = std::min(t + step, tb);
            const double fn = f(tn);
            if (fn <= 0)
            {
                // Bracketed crossing: a few regula-falsi steps.
                double lo = t;
                double hi = tn;
                double flo = ft;
                double fhi = fn;
                for (int k = 0; k < 4; ++k)
                {
                    const double mid = lo + (hi - lo) * flo / (flo - fhi);
                    const double fm = f(mid);
                    if (fm > 0)
                    {
                        lo = mid;
                        flo = fm;
                    }
                    else
                    {
                        hi = mid;
                        fhi = fm;
                    }
                }
                return lo + (hi - lo) * flo / (flo - fhi);
            }
            t = tn;
            ft = fn;
        }
        return -1;
    }

    float shade(const Prepared& e, int axis, const Vec3& d, double t) const
    {
        const Vec3 q{m_o[0] + t * d[0], m_o[1] + t * d[1], m_o[2] + t * d[2]};
        // Pixel footprint on the surface [m]: distance / f, widened by the
        // obliquity (geometric mean of the footprint's two axes).
        const double dn = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const double cos_inc = std::max(std::abs(d[static_cast<std::size_t>(axis)]) / dn, 0.05);
        const double foot = t * dn * m_inv_f / std::sqrt(cos_inc);
        if (e.kind == Element::Kind::HeightField)
        {
            const HeightField& hf = m_world.heightField();
            const float s = bilinear(hf.shade, (q[0] - hf.x0) / hf.cell, (q[2] - hf.z0) / hf.cell);
            return s *
                   e.tex->sampleWrapLod(q[0] * e.inv_texel, q[2] * e.inv_texel, foot * e.inv_texel);
        }
        // In-plane texture axes: (z, y) for X planes, (x, z) for Y, (x, y) for Z.
        const std::size_t a = axis == 0 ? 2 : 0;
        const std::size_t b = axis == 1 ? 2 : 1;
        float light = 1.0F;
        if (axis == 0)
        {
            light = 0.82F;
        }
        else if (axis == 2)
        {
            light = 0.94F;
        }
        else if (d[1] > 0)
        {
            light = 0.78F;  // seen from below: a ceiling or a box bottom
        }
        if (e.stretch)
        {
            const double u = (q[a] - e.lo[a]) / std::max(e.hi[a] - e.lo[a], 1e-9);
            const double v = (e.hi[b] - q[b]) / std::max(e.hi[b] - e.lo[b], 1e-9);
            const double extent = std::max(e.hi[a] - e.lo[a], e.hi[b] - e.lo[b]);
            return light * e.tex->sampleClampLod(u, v, foot * e.tex->size() / extent);
        }
        double s = q[a];
        double r = -q[b];
        if (e.box_local)
        {
            s -= e.lo[a];
            r += e.lo[b];
        }
        return light * e.tex->sampleWrapLod(s * e.inv_texel, r * e.inv_texel, foot * e.inv_texel);
    }

    const World& m_world;
    std::vector<Prepared> m_els;
    Vec3 m_o;
    double m_max;
    double m_inv_f;
};
}  // namespace

void StereoRenderer::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    MRPT_LOAD_CONFIG_VAR(width, int, c, s);
    MRPT_LOAD_CONFIG_VAR(height, int, c, s);
    MRPT_LOAD_CONFIG_VAR(focal_px, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cx, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cy, double, c, s);
    MRPT_LOAD_CONFIG_VAR(baseline, double, c, s);
    MRPT_LOAD_CONFIG_VAR(supersampling, int, c, s);
    MRPT_LOAD_CONFIG_VAR(noise_sigma, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_range, double, c, s);
    validate();
}

void StereoRenderer::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    MRPT_SAVE_CONFIG_VAR(width, c, s);
    MRPT_SAVE_CONFIG_VAR(height, c, s);
    MRPT_SAVE_CONFIG_VAR(focal_px, c, s);
    MRPT_SAVE_CONFIG_VAR(cx, c, s);
    MRPT_SAVE_CONFIG_VAR(cy, c, s);
    MRPT_SAVE_CONFIG_VAR(baseline, c, s);
    MRPT_SAVE_CONFIG_VAR(supersampling, c, s);
    MRPT_SAVE_CONFIG_VAR(noise_sigma, c, s);
    MRPT_SAVE_CONFIG_VAR(max_range, c, s);
}

void StereoRenderer::TParameters::validate() const
{
    if (width < 8 || width > 8192)
    {
        bad("width", "must be in 8..8192 (got " + std::to_string(width) + ")");
    }
    if (height < 8 || height > 8192)
    {
        bad("height", "must be in 8..8192 (got " + std::to_string(height) + ")");
    }
    if (!(focal_px > 0 && focal_px <= 1e6))
    {
        bad("focal_px", "must be in (0, 1e6] (got " + std::to_string(focal_px) + ")");
    }
    // < 0: the image centre.
    if (!(std::abs(cx) <= 1e6) || !(std::abs(cy) <= 1e6))
    {
        bad(std::abs(cx) <= 1e6 ? "cy" : "cx", "must be in [-1e6, 1e6] px (< 0: image centre)");
    }
    if (!(baseline > 0 && baseline <= 1000))
    {
        bad("baseline", "must be in (0, 1000] m (got " + std::to_string(baseline) + ")");
    }
    if (supersampling < 1 || supersampling > 4)
    {
        bad("supersampling", "must be in 1..4 (got " + std::to_string(supersampling) + ")");
    }
    if (!(noise_sigma >= 0 && noise_sigma <= 255))
    {
        bad("noise_sigma", "must be in [0, 255] (got " + std::to_string(noise_sigma) + ")");
    }
    if (!(max_range > 0 && max_range <= 1e6))
    {
        bad("max_range", "must be in (0, 1e6] m (got " + std::to_string(max_range) + ")");
    }
}

void StereoRenderer::setParameters(const TParameters& p)
{
    p.validate();
    m_p = p;
}

mrpt::img::TStereoCamera StereoRenderer::stereoCamera() const
{
    mrpt::img::TStereoCamera c;
    const double cx = m_p.cx >= 0 ? m_p.cx : (m_p.width - 1) / 2.0;
    const double cy = m_p.cy >= 0 ? m_p.cy : (m_p.height - 1) / 2.0;
    for (auto* cam : {&c.leftCamera, &c.rightCamera})
    {
        cam->ncols = static_cast<uint32_t>(m_p.width);
        cam->nrows = static_cast<uint32_t>(m_p.height);
        cam->setIntrinsicParamsFromValues(m_p.focal_px, m_p.focal_px, cx, cy);
        cam->distortion = mrpt::img::DistortionModel::none;
        cam->dist.fill(0);
    }
    c.leftCamera.cameraName = "left";
    c.rightCamera.cameraName = "right";
    c.rightCameraPose = mrpt::math::TPose3DQuat(m_p.baseline, 0, 0, 1, 0, 0, 0);
    return c;
}

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

    const Caster caster(world, std::move(els), o, m_p.max_range, f);
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
