// SPDX-License-Identifier: BSD-3-Clause
// RayCaster: closest hit of a ray among planes and boxes, height-field ray
// marching with empty-space skipping, and texture shading of the hit.
#include "RayCaster.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace emslam::sim::detail
{
namespace
{
/** Intensity of a ray that hits nothing (a bright, flat sky). */
constexpr float SKY = 205.0F;

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

/** Clips the ray o + t d, t in [ta, tb], to the element's bounding box;
 * false: it misses the box. */
bool clipToBox(const Prepared& e, const Vec3& o, const Vec3& d, double& ta, double& tb)
{
    for (std::size_t a = 0; a < 3; ++a)
    {
        if (d[a] == 0.0)
        {
            if (o[a] < e.lo[a] || o[a] > e.hi[a])
            {
                return false;
            }
            continue;
        }
        double t1 = (e.lo[a] - o[a]) / d[a];
        double t2 = (e.hi[a] - o[a]) / d[a];
        if (t1 > t2)
        {
            std::swap(t1, t2);
        }
        ta = std::max(ta, t1);
        tb = std::min(tb, t2);
    }
    return ta < tb;
}

/** What empty-space skipping did with a ray at t. */
enum class Skip
{
    None,    //!< march from t
    Jumped,  //!< t moved to a cell's exit: look again
    Past,    //!< t left the field
};

/** A ray o + t d (t < tb) over a height field: its height above the ground,
 * and the empty-space skipping and root finding of the march. */
struct HeightFieldRay
{
    HeightFieldRay(const HeightField& field, const Vec3& origin, const Vec3& dir, double t_end)
        : hf(field),
          o(origin),
          d(dir),
          tb(t_end),
          inv_cell(1.0 / field.cell),
          fx_max(field.heights.cols - 1.001),
          fz_max(field.heights.rows - 1.001),
          bsize(field.cell * HeightField::BLOCK),
          inv_bsize(1.0 / bsize),
          csize(bsize * HeightField::COARSE)
    {
    }

    /** The ray's height above the ground at t: HeightField::at() with
     * multiplications instead of divisions (hot loop). */
    double height(double t) const
    {
        const double fx = std::clamp((o[0] + t * d[0] - hf.x0) * inv_cell, 0.0, fx_max);
        const double fz = std::clamp((o[2] + t * d[2] - hf.z0) * inv_cell, 0.0, fz_max);
        const int ix = static_cast<int>(fx);
        const int iz = static_cast<int>(fz);
        const double ax = fx - ix;
        const double az = fz - iz;
        const float* r0 = hf.heights.ptr<float>(iz) + ix;
        const float* r1 = hf.heights.ptr<float>(iz + 1) + ix;
        const double h =
            (r0[0] * (1 - ax) + r0[1] * ax) * (1 - az) + (r1[0] * (1 - ax) + r1[1] * ax) * az;
        return o[1] + t * d[1] - h;
    }

    /** Exit t of the ray from grid cell (ix, iz) of edge size. */
    double cellExit(double size, int ix, int iz) const
    {
        double t_exit = tb;
        if (d[0] != 0.0)
        {
            const double xe = hf.x0 + (d[0] > 0 ? ix + 1 : ix) * size;
            t_exit = std::min(t_exit, (xe - o[0]) / d[0]);
        }
        if (d[2] != 0.0)
        {
            const double ze = hf.z0 + (d[2] > 0 ? iz + 1 : iz) * size;
            t_exit = std::min(t_exit, (ze - o[2]) / d[2]);
        }
        return t_exit;
    }

    /** Empty-space skipping (coarse cells, then blocks): if the ray stays
     * above a cell's highest sample until it leaves the cell, jump to the
     * cell's exit; if it sinks below it inside, jump to where it does.
     * Updates t and ft = height(t). */
    Skip skipEmptySpace(double& t, double& ft) const
    {
        const double x = o[0] + t * d[0];
        const double z = o[2] + t * d[2];
        const double y = o[1] + t * d[1];
        const int bx =
            std::clamp(static_cast<int>((x - hf.x0) * inv_bsize), 0, hf.block_max.cols - 1);
        const int bz =
            std::clamp(static_cast<int>((z - hf.z0) * inv_bsize), 0, hf.block_max.rows - 1);
        double cmax = hf.block_max.at<float>(bz, bx);
        if (y <= cmax)
        {
            return Skip::None;
        }
        double t_exit = tb;
        const int cx = std::min(bx / HeightField::COARSE, hf.coarse_max.cols - 1);
        const int cz = std::min(bz / HeightField::COARSE, hf.coarse_max.rows - 1);
        const double c_max = hf.coarse_max.at<float>(cz, cx);
        bool coarse = false;
        if (y > c_max)
        {
            t_exit = cellExit(csize, cx, cz);
            coarse = d[1] >= 0 || o[1] + t_exit * d[1] > c_max;
            cmax = c_max;
        }
        if (!coarse)
        {
            t_exit = cellExit(bsize, bx, bz);
            cmax = hf.block_max.at<float>(bz, bx);
        }
        if (t_exit <= t)
        {
            return Skip::None;
        }
        if (d[1] >= 0 || o[1] + t_exit * d[1] > cmax)
        {
            t = t_exit + 1e-6;
            if (t >= tb)
            {
                return Skip::Past;
            }
            ft = height(t);
            return Skip::Jumped;
        }
        // No crossing before the ray sinks below the cell's maximum.
        t = (cmax - o[1]) / d[1];
        ft = height(t);
        return Skip::None;
    }

    /** The ground crossing bracketed by [lo, hi] (heights flo > 0 >= fhi):
     * a few regula-falsi steps. */
    double crossing(double lo, double hi, double flo, double fhi) const
    {
        for (int k = 0; k < 4; ++k)
        {
            const double mid = lo + (hi - lo) * flo / (flo - fhi);
            const double fm = height(mid);
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

    const HeightField& hf;
    const Vec3& o;
    const Vec3& d;
    const double tb;
    const double inv_cell, fx_max, fz_max;
    const double bsize, inv_bsize, csize;
};
}  // namespace

float RayCaster::cast(const Vec3& d, const std::vector<int>& cand, double& t_hit) const
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

double RayCaster::castHeightField(const Prepared& e, const Vec3& d, double t_limit) const
{
    double ta = NEAR;
    double tb = t_limit;
    if (!clipToBox(e, m_o, d, ta, tb))
    {
        return -1;
    }
    const HeightFieldRay r(m_world.heightField(), m_o, d, tb);
    const double denom = r.hf.max_slope * std::sqrt(d[0] * d[0] + d[2] * d[2]) + std::abs(d[1]);
    const double dn = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double t = ta;
    double ft = r.height(t);
    if (ft <= 0)
    {
        return -1;  // starts under the ground
    }
    for (int it = 0; it < 1000 && t < tb; ++it)
    {
        const Skip skip = r.skipEmptySpace(t, ft);
        if (skip == Skip::Past)
        {
            break;
        }
        if (skip == Skip::Jumped)
        {
            continue;
        }
        const double step = std::max(0.8 * ft / denom, (0.05 + 0.012 * t) / dn);
        const double tn = std::min(t + step, tb);
        const double fn = r.height(tn);
        if (fn <= 0)
        {
            return r.crossing(t, tn, ft, fn);
        }
        t = tn;
        ft = fn;
    }
    return -1;
}

float RayCaster::shade(const Prepared& e, int axis, const Vec3& d, double t) const
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
        return s * e.tex->sampleWrapLod(q[0] * e.inv_texel, q[2] * e.inv_texel, foot * e.inv_texel);
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

}  // namespace emslam::sim::detail
