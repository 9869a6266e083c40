// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/stereo/VerticalFromPlanes.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace emslam::stereo
{
namespace
{
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Mat32 = Eigen::Matrix<double, 3, 2>;

constexpr double CHI2_2DOF_MEDIAN = 1.386;  // of a χ²(2)
constexpr double CHI2_2DOF_OUTLIER = 9.21;  // 99 % of a χ²(2)

Vec3 toEigen(const mrpt::math::TVector3D& v)
{
    return {v.x, v.y, v.z};
}

/** Two unit vectors orthogonal to unit `n` and to each other. */
Mat32 tangentBasis(const Vec3& n)
{
    Mat32 E;
    E << n.unitOrthogonal(), n.cross(n.unitOrthogonal());
    return E;
}

/** The normal of one patch's disparity plane, in the tangent plane of the
 * predicted up (`m`, two angles), with its covariance `C`. */
struct PatchNormal
{
    Vec2 m;
    Mat2 W;                  // information
    double residual_var{0};  // of the disparities about the plane [px²]
};

std::optional<PatchNormal> fitPatch(
    const cv::Mat& disparity,
    const cv::Mat& valid,
    int u_begin,
    int v_begin,
    int side,
    const mrpt::img::TCamera& cam,
    const Vec3& predicted,
    const Mat32& E,
    double cos_max_angle)
{
    // Normal equations of d = a (u - u0) + b (v - v0) + c.
    const double u0 = u_begin + 0.5 * (side - 1);
    const double v0 = v_begin + 0.5 * (side - 1);
    Mat3 AtA = Mat3::Zero();
    Vec3 Atd = Vec3::Zero();
    double dtd = 0;
    int n = 0;
    for (int v = v_begin; v < v_begin + side; ++v)
    {
        const auto* drow = disparity.ptr<float>(v);
        const auto* mrow = valid.empty() ? nullptr : valid.ptr<std::uint8_t>(v);
        for (int u = u_begin; u < u_begin + side; ++u)
        {
            const double d = drow[u];
            if (!(d > 0) || !std::isfinite(d) || (mrow != nullptr && mrow[u] == 0))
            {
                continue;
            }
            const Vec3 row(u - u0, v - v0, 1.0);
            AtA += row * row.transpose();
            Atd += row * d;
            dtd += d * d;
            ++n;
        }
    }
    if (n < std::max(12, side * side / 3))
    {
        return std::nullopt;
    }
    const Eigen::LDLT<Mat3> ldlt(AtA);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0))
    {
        return std::nullopt;
    }
    const Vec3 p = ldlt.solve(Atd);
    const double sse = std::max(0.0, dtd - p.dot(Atd));
    // A floor of the noise: sub-pixel disparities are not better than this.
    const double s2 = std::max(sse / (n - 3), 1e-4);
    const Mat3 P = s2 * ldlt.solve(Mat3::Identity());
    // fx·B = a·fx·X + b·fy·Y + (a (cx - u0) + b (cy - v0) + c)·Z
    Mat3 J;
    J << cam.fx(), 0, 0, 0, cam.fy(), 0, cam.cx() - u0, cam.cy() - v0, 1;
    Vec3 normal = J * p;
    const double len = normal.norm();
    if (!(len > 0))
    {
        return std::nullopt;
    }
    normal /= len;
    double sign = 1;
    if (normal.dot(predicted) < 0)
    {
        normal = -normal;
        sign = -1;
    }
    if (normal.dot(predicted) < cos_max_angle)
    {
        return std::nullopt;  // a wall, a slope
    }
    const Mat3 Jn = sign * (Mat3::Identity() - normal * normal.transpose()) / len;
    const Mat3 C3 = Jn * J * P * J.transpose() * Jn.transpose();
    const Mat2 C = E.transpose() * C3 * E + 1e-12 * Mat2::Identity();
    PatchNormal out;
    out.m = E.transpose() * normal;
    out.W = C.inverse();
    out.residual_var = s2;
    if (!out.W.allFinite())
    {
        return std::nullopt;
    }
    return out;
}

struct Fused
{
    Vec2 mean;
    Mat2 information;
    double chi2{0};
    std::vector<double> d2;  // per patch
};

Fused fuse(const std::vector<PatchNormal>& patches, const std::vector<bool>& use)
{
    Fused f;
    f.information.setZero();
    Vec2 eta = Vec2::Zero();
    for (std::size_t i = 0; i < patches.size(); ++i)
    {
        if (use[i])
        {
            f.information += patches[i].W;
            eta += patches[i].W * patches[i].m;
        }
    }
    f.mean = f.information.ldlt().solve(eta);
    f.d2.resize(patches.size());
    for (std::size_t i = 0; i < patches.size(); ++i)
    {
        const Vec2 r = patches[i].m - f.mean;
        f.d2[i] = r.dot(patches[i].W * r);
        if (use[i])
        {
            f.chi2 += f.d2[i];
        }
    }
    return f;
}
}  // namespace

mrpt::math::CMatrixDouble33 VerticalMeasurement::information() const
{
    const Vec3 n = toEigen(up).normalized();
    const Mat32 E = tangentBasis(n);
    const Mat2 C2 = E.transpose() * covariance.asEigen() * E;
    mrpt::math::CMatrixDouble33 out;
    out.asEigen() = E * C2.inverse() * E.transpose();
    return out;
}

namespace
{
/** Every key, once for load and save. */
void visit(VerticalFromPlanes::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("patch_px", p.patch_px, "[px] side of a plane patch of the disparity");
    v.field("max_angle_deg", p.max_angle_deg, "[deg] patches farther from the predicted up: walls");
    v.field("min_patches", p.min_patches, "level patches a measurement needs");
}
}  // namespace

void VerticalFromPlanes::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
}

void VerticalFromPlanes::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void VerticalFromPlanes::TParameters::validate() const
{
    if (patch_px < 4)
    {
        throw std::invalid_argument(
            "[VerticalFromPlanes] patch_px must be at least 4 (got " + std::to_string(patch_px) +
            ")");
    }
    if (!(max_angle_deg > 0 && max_angle_deg < 90))
    {
        throw std::invalid_argument(
            "[VerticalFromPlanes] max_angle_deg must be in (0, 90) (got " +
            std::to_string(max_angle_deg) + ")");
    }
    if (min_patches < 2)
    {
        throw std::invalid_argument(
            "[VerticalFromPlanes] min_patches must be at least 2 (got " +
            std::to_string(min_patches) + ")");
    }
}

VerticalFromPlanes::VerticalFromPlanes(const TParameters& p) : m_p(p)
{
    m_p.validate();
}

std::optional<VerticalMeasurement> VerticalFromPlanes::measure(
    const StereoFrame& f, const mrpt::math::TVector3D& predicted_up) const
{
    const cv::Mat& disp = f.disparity;
    if (disp.empty() || disp.type() != CV_32FC1 ||
        (!f.valid.empty() && f.valid.size() != disp.size()))
    {
        return std::nullopt;
    }
    Vec3 predicted = toEigen(predicted_up);
    if (!(predicted.norm() > 0) || !predicted.allFinite())
    {
        return std::nullopt;
    }
    predicted.normalize();
    const Mat32 E = tangentBasis(predicted);
    const double cos_max = std::cos(m_p.max_angle_deg * M_PI / 180.0);
    const int side = m_p.patch_px;
    std::vector<PatchNormal> patches;
    for (int v = 0; v + side <= disp.rows; v += side)
    {
        for (int u = 0; u + side <= disp.cols; u += side)
        {
            if (auto p =
                    fitPatch(disp, f.valid, u, v, side, f.camera.leftCamera, predicted, E, cos_max))
            {
                patches.push_back(*p);
            }
        }
    }
    if (patches.size() < static_cast<std::size_t>(m_p.min_patches))
    {
        return std::nullopt;
    }
    // A patch across an edge (a stair's nosing, a skirting board) fits a
    // plane between the two, tilted, with a residual beyond the noise of
    // the flat patches: keep those within twice the median's deviation.
    std::vector<double> var;
    var.reserve(patches.size());
    for (const auto& p : patches)
    {
        var.push_back(p.residual_var);
    }
    std::nth_element(var.begin(), var.begin() + static_cast<long>(var.size() / 2), var.end());
    const double max_var = 4 * var[var.size() / 2];
    std::vector<bool> use(patches.size());
    for (std::size_t i = 0; i < patches.size(); ++i)
    {
        use[i] = patches[i].residual_var <= max_var;
    }
    const auto count = [&use]
    { return static_cast<std::size_t>(std::count(use.begin(), use.end(), true)); };
    if (count() < static_cast<std::size_t>(m_p.min_patches))
    {
        return std::nullopt;
    }
    // Patches that disagree with the rest beyond their own noise (a slope,
    // an object): twice, drop those outside the 99 % of the others' scatter.
    Fused fused = fuse(patches, use);
    for (int pass = 0; pass < 2; ++pass)
    {
        std::vector<double> d2;
        for (std::size_t i = 0; i < patches.size(); ++i)
        {
            if (use[i])
            {
                d2.push_back(fused.d2[i]);
            }
        }
        std::nth_element(d2.begin(), d2.begin() + static_cast<long>(d2.size() / 2), d2.end());
        const double scale = std::max(1.0, d2[d2.size() / 2] / CHI2_2DOF_MEDIAN);
        for (std::size_t i = 0; i < patches.size(); ++i)
        {
            use[i] = use[i] && fused.d2[i] <= CHI2_2DOF_OUTLIER * scale;
        }
        if (count() < static_cast<std::size_t>(m_p.min_patches))
        {
            return std::nullopt;
        }
        fused = fuse(patches, use);
    }
    const std::size_t kept = count();
    VerticalMeasurement out;
    out.patches = kept;
    out.dispersion = std::max(1.0, fused.chi2 / static_cast<double>(2 * (kept - 1)));
    const Vec3 up = (predicted + E * fused.mean).normalized();
    out.up = {up.x(), up.y(), up.z()};
    out.covariance.asEigen() = E * (out.dispersion * fused.information.inverse()) * E.transpose();
    return out;
}

}  // namespace emslam::stereo
