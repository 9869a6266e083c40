// SPDX-License-Identifier: BSD-3-Clause
// SurfaceSampler: samples of every static face of a World, and the ones the
// trajectory's cameras saw (a depth test against the renderer's exact depth).
#include <emslam/sim/SurfaceSampler.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace emslam::sim
{
namespace
{
/** Every key of the section, once for load and save. */
void visit(SurfaceSampler::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("spacing", p.spacing, "[m] distance between samples");
    v.field("max_range", p.max_range, "[m] farthest depth a sample is seen at");
    v.field("min_range", p.min_range, "[m] nearest depth a sample is seen at");
    v.field("pose_step", p.pose_step, "[m] camera motion between tested frames");
    v.field("pose_step_deg", p.pose_step_deg, "[deg] camera turn between tested frames");
}
}  // namespace

void SurfaceSampler::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
}

void SurfaceSampler::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void SurfaceSampler::TParameters::validate() const
{
    const auto require = [](bool ok, const char* key, const char* what)
    {
        if (!ok)
        {
            throw std::invalid_argument(std::string("SurfaceSampler: ") + key + " " + what);
        }
    };
    require(spacing >= 0.001 && spacing <= 10, "spacing", "must be in [0.001, 10] m");
    require(min_range >= 0 && std::isfinite(min_range), "min_range", "must be >= 0 m");
    require(max_range > min_range && std::isfinite(max_range), "max_range", "must be > min_range");
    require(pose_step > 0 && std::isfinite(pose_step), "pose_step", "must be > 0 m");
    require(pose_step_deg > 0 && pose_step_deg <= 180, "pose_step_deg", "must be in (0, 180] deg");
}

SurfaceSampler::SurfaceSampler(const TParameters& p) : m_p(p)
{
    m_p.validate();
}

namespace
{
/** Samples of the axis-aligned rectangle normal to `axis` at lo[axis],
 * spanning [lo, hi] on the two other axes: cell centres of a grid of about
 * `spacing`. */
void sampleRectangle(
    int axis, const Vec3& lo, const Vec3& hi, double spacing, std::vector<SurfaceSample>& out)
{
    const auto a = static_cast<std::size_t>(axis == 0 ? 1 : 0);
    const auto b = static_cast<std::size_t>(axis == 2 ? 1 : 2);
    const double la = hi[a] - lo[a], lb = hi[b] - lo[b];
    const int na = std::max(1, static_cast<int>(std::ceil(la / spacing - 1e-9)));
    const int nb = std::max(1, static_cast<int>(std::ceil(lb / spacing - 1e-9)));
    SurfaceSample s;
    s.normal[static_cast<std::size_t>(axis)] = 1.0;
    s.position[static_cast<std::size_t>(axis)] = lo[static_cast<std::size_t>(axis)];
    for (int i = 0; i < na; ++i)
    {
        s.position[a] = lo[a] + (i + 0.5) * la / na;
        for (int j = 0; j < nb; ++j)
        {
            s.position[b] = lo[b] + (j + 0.5) * lb / nb;
            out.push_back(s);
        }
    }
}

void sampleHeightField(
    const HeightField& h, const Element& e, double spacing, std::vector<SurfaceSample>& out)
{
    const double lx = e.hi[0] - e.lo[0], lz = e.hi[2] - e.lo[2];
    const int nx = std::max(1, static_cast<int>(std::ceil(lx / spacing - 1e-9)));
    const int nz = std::max(1, static_cast<int>(std::ceil(lz / spacing - 1e-9)));
    const double d = 0.5 * spacing;
    for (int i = 0; i < nx; ++i)
    {
        const double x = e.lo[0] + (i + 0.5) * lx / nx;
        for (int j = 0; j < nz; ++j)
        {
            const double z = e.lo[2] + (j + 0.5) * lz / nz;
            // Normal of the surface y = h(x, z): (-dh/dx, 1, -dh/dz), normalised.
            const double gx = (h.at(x + d, z) - h.at(x - d, z)) / (2 * d);
            const double gz = (h.at(x, z + d) - h.at(x, z - d)) / (2 * d);
            const double n = std::sqrt(gx * gx + 1 + gz * gz);
            SurfaceSample s;
            s.position = {x, h.at(x, z), z};
            s.normal = {-gx / n, 1 / n, -gz / n};
            out.push_back(s);
        }
    }
}

/** Angle between the viewing directions (camera +z) of two poses [rad]. */
double viewAngle(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
    const auto ra = a.getRotationMatrix();
    const auto rb = b.getRotationMatrix();
    double dot = 0;
    for (int k = 0; k < 3; ++k)
    {
        dot += ra(k, 2) * rb(k, 2);
    }
    return std::acos(std::clamp(dot, -1.0, 1.0));
}

/** R^T n: a scene direction in the frame whose rotation is R. */
Vec3 rotateBack(const mrpt::math::CMatrixDouble33& R, const Vec3& n)
{
    Vec3 out;
    for (int r = 0; r < 3; ++r)
    {
        out[static_cast<std::size_t>(r)] = R(0, r) * n[0] + R(1, r) * n[1] + R(2, r) * n[2];
    }
    return out;
}

/** The pinhole camera of the rendered depth images. */
struct Pinhole
{
    double fx, fy, cx, cy;
};

/** True if the four pixel centres around the projection of the sample at
 * `p` (camera frame, normal `n`) all see the sample's own plane: each
 * rendered depth equals, to float precision, the depth at which that
 * pixel's ray meets the plane. A sample within a pixel of an occluding edge
 * fails (one of the four sees the occluder), which a depth test at the
 * projection alone would not catch: there the rendered depths jump, and any
 * depth interpolated between them may match. */
bool seesOwnPlane(const cv::Mat& depth, const Pinhole& c, const Vec3& p, const Vec3& n)
{
    const double u = c.fx * p[0] / p[2] + c.cx;
    const double v = c.fy * p[1] / p[2] + c.cy;
    const int u0 = static_cast<int>(std::floor(u));
    const int v0 = static_cast<int>(std::floor(v));
    if (u0 < 0 || v0 < 0 || u0 + 1 >= depth.cols || v0 + 1 >= depth.rows)
    {
        return false;
    }
    const double np = n[0] * p[0] + n[1] * p[1] + n[2] * p[2];
    for (int dv = 0; dv <= 1; ++dv)
    {
        const float* row = depth.ptr<float>(v0 + dv);
        for (int du = 0; du <= 1; ++du)
        {
            // Ray (x, y, 1) of the pixel centre; the plane n . X = n . p.
            const double rx = (u0 + du - c.cx) / c.fx, ry = (v0 + dv - c.cy) / c.fy;
            const double nr = n[0] * rx + n[1] * ry + n[2];
            if (std::abs(nr) < 1e-9)
            {
                return false;
            }
            const double z_plane = np / nr;
            const double d = row[u0 + du];
            if (!(d > 0) || std::abs(d - z_plane) > 0.005 + 0.002 * z_plane)
            {
                return false;
            }
        }
    }
    return true;
}
}  // namespace

std::vector<SurfaceSample> SurfaceSampler::allSurfaces(const World& world) const
{
    std::vector<SurfaceSample> out;
    for (const Element& e : world.elements())
    {
        switch (e.kind)
        {
            case Element::Kind::Plane:
                sampleRectangle(e.axis, e.lo, e.hi, m_p.spacing, out);
                break;
            case Element::Kind::Box:
                if (e.moving())
                {
                    break;
                }
                for (int axis = 0; axis < 3; ++axis)
                {
                    Vec3 top = e.lo;
                    top[static_cast<std::size_t>(axis)] = e.hi[static_cast<std::size_t>(axis)];
                    Vec3 far = e.hi;
                    far[static_cast<std::size_t>(axis)] = e.lo[static_cast<std::size_t>(axis)];
                    sampleRectangle(axis, e.lo, far, m_p.spacing, out);
                    sampleRectangle(axis, top, e.hi, m_p.spacing, out);
                }
                break;
            case Element::Kind::HeightField:
                sampleHeightField(world.heightField(), e, m_p.spacing, out);
                break;
        }
    }
    return out;
}

std::vector<std::size_t> SurfaceSampler::testedFrames(
    const StereoSimulator& sim, std::size_t frames) const
{
    std::vector<std::size_t> out;
    mrpt::poses::CPose3D last;
    for (std::size_t i = 0; i < std::min(frames, sim.frameCount()); ++i)
    {
        const auto pose = sim.scenePose(i);
        if (out.empty() || (pose.translation() - last.translation()).norm() >= m_p.pose_step ||
            viewAngle(pose, last) >= mrpt::DEG2RAD(m_p.pose_step_deg))
        {
            out.push_back(i);
            last = pose;
        }
    }
    return out;
}

std::vector<SurfaceSample> SurfaceSampler::visibleSurfaces(
    const StereoSimulator& sim, std::size_t frames) const
{
    std::vector<SurfaceSample> all = allSurfaces(sim.world());
    std::vector<float> seen(all.size(), 0.0F);
    const auto cam = sim.renderer().stereoCamera().leftCamera;
    const Pinhole pinhole{cam.fx(), cam.fy(), cam.cx(), cam.cy()};
    cv::Mat intensity, depth;
    for (const std::size_t i : testedFrames(sim, frames))
    {
        const auto T_scene_cam = sim.scenePose(i);
        const auto R = T_scene_cam.getRotationMatrix();
        sim.renderer().renderView(
            sim.world(), T_scene_cam, static_cast<double>(i) / sim.params().fps, intensity, &depth);
        for (std::size_t k = 0; k < all.size(); ++k)
        {
            const Vec3& q = all[k].position;
            Vec3 p;
            T_scene_cam.inverseComposePoint(q[0], q[1], q[2], p[0], p[1], p[2]);
            if (!(p[2] >= m_p.min_range && p[2] <= m_p.max_range) ||
                (seen[k] > 0 && seen[k] <= static_cast<float>(p[2])))
            {
                continue;
            }
            if (seesOwnPlane(depth, pinhole, p, rotateBack(R, all[k].normal)))
            {
                seen[k] = static_cast<float>(p[2]);
            }
        }
    }
    const auto T_scene_first = sim.scenePose(0);
    const auto R = T_scene_first.getRotationMatrix();
    std::vector<SurfaceSample> out;
    for (std::size_t k = 0; k < all.size(); ++k)
    {
        if (seen[k] <= 0)
        {
            continue;
        }
        SurfaceSample s;
        const Vec3& p = all[k].position;
        T_scene_first.inverseComposePoint(
            p[0], p[1], p[2], s.position[0], s.position[1], s.position[2]);
        s.normal = rotateBack(R, all[k].normal);
        s.seen_range = seen[k];
        out.push_back(s);
    }
    return out;
}

}  // namespace emslam::sim
