// SPDX-License-Identifier: BSD-3-Clause
// Private to emslam_sim (not installed): the ray caster of one view, shared by
// StereoRenderer::renderView() (which culls and bins the elements into image
// tiles) and RayCaster.cpp (intersection, height-field marching, shading).
#pragma once

#include <emslam/sim/World.h>

#include <utility>
#include <vector>

namespace emslam::sim::detail
{
/** Nearest hit distance [m]; also the near plane that clips the elements'
 * image footprints. */
constexpr double NEAR = 0.01;

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

/** Ray caster for one view: casts rays from the camera centre `o` against
 * the Prepared elements of that view. */
class RayCaster
{
public:
    RayCaster(
        const World& w, std::vector<Prepared> els, const Vec3& o, double max_range, double focal)
        : m_world(w), m_els(std::move(els)), m_o(o), m_max(max_range), m_inv_f(1.0 / focal)
    {
    }

    /** Closest hit along o + t d (t: camera depth since d_cam.z == 1); returns
     * the intensity, and t (0: nothing). */
    float cast(const Vec3& d, const std::vector<int>& cand, double& t_hit) const;

private:
    /** Depth of the first crossing of the height field along d before
     * `t_limit`, or -1. */
    double castHeightField(const Prepared& e, const Vec3& d, double t_limit) const;
    /** Intensity of element `e` hit at depth t on its face normal to `axis`. */
    float shade(const Prepared& e, int axis, const Vec3& d, double t) const;

    const World& m_world;
    std::vector<Prepared> m_els;
    Vec3 m_o;
    double m_max;
    double m_inv_f;
};

}  // namespace emslam::sim::detail
