// SPDX-License-Identifier: BSD-3-Clause
#include "PoseEigen.h"

#include <emslam/egomotion/StereoReprojectionRefinement.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace emslam::egomotion
{
namespace
{
using detail::Mat3;
using detail::Mat6;
using detail::Vec3;
using detail::Vec6;
using Mat36 = Eigen::Matrix<double, 3, 6>;

/** A point this close to a camera's image plane [m] has no usable
 * projection (the disparity B/z would blow up). */
constexpr double MIN_DEPTH = 1e-3;

Mat3 skew(const Vec3& v)
{
    Mat3 s;
    s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return s;
}

/** Image coordinates of a camera-frame point: (x/z, y/z, B/z). */
Vec3 project(const Vec3& p, double baseline)
{
    return {p.x() / p.z(), p.y() / p.z(), baseline / p.z()};
}

/** d project / d p. */
Mat3 projectJacobian(const Vec3& p, double baseline)
{
    const double iz = 1.0 / p.z(), iz2 = iz * iz;
    Mat3 J;
    J << iz, 0, -p.x() * iz2, 0, iz, -p.y() * iz2, 0, 0, -baseline * iz2;
    return J;
}

/** d p / d (its image coordinates (x/z, y/z, B/z)): how a point's
 * measurement noise moves it. */
Mat3 triangulationJacobian(const Vec3& p, double baseline)
{
    const double z = p.z(), k = -z / baseline;
    Mat3 J;
    J << z, 0, k * p.x(), 0, z, k * p.y(), 0, 0, k * z;
    return J;
}

struct Problem
{
    std::vector<Vec3> a, b;            //!< previous / current frame points
    std::vector<Vec3> proj_a, proj_b;  //!< their own image coordinates
    double baseline{0};
    /** Measurement variance of each image coordinate (x/z, y/z, B/z). */
    Vec3 sigma2{1, 1, 1};
};

/** One direction of one pair: the point `s` of one frame, moved into the
 * other camera (c = A s + u, with dc/d[δt, w] = `dc`), against that
 * frame's measurement `m`. Both were measured, so the residual's
 * covariance is the measurement's plus the moved point's:
 * Σ = S + M S Mᵀ, M = dπ(c)/dc · A · d s/d(its image coordinates). */
struct Direction
{
    Vec3 r;      //!< raw residual π(c) − m
    Mat3 P;      //!< dπ/dc
    Mat3 Sigma;  //!< its covariance
};

Direction direction(const Problem& p, const Vec3& s, const Vec3& c, const Mat3& A, const Vec3& m)
{
    Direction d;
    d.r = project(c, p.baseline) - m;
    d.P = projectJacobian(c, p.baseline);
    const Mat3 M = d.P * A * triangulationJacobian(s, p.baseline);
    d.Sigma = M * p.sigma2.asDiagonal() * M.transpose();
    d.Sigma.diagonal() += p.sigma2;
    return d;
}

/** Huber's loss of a whitened residual, k = 1.345 (95 % efficiency on
 * Gaussian data), and its IRLS weight. */
constexpr double HUBER_K = 1.345;
double huber(double n)
{
    return n <= HUBER_K ? 0.5 * n * n : HUBER_K * (n - 0.5 * HUBER_K);
}
double huberWeight(double n)
{
    return n <= HUBER_K ? 1.0 : HUBER_K / n;
}

/** Both directions of pair i at (R, t), with dc/d[δt, w] of each
 * (R ← exp(w) R, t ← t + δt); false if the point falls behind a camera. */
bool directions(
    const Problem& p,
    std::size_t i,
    const Mat3& R,
    const Vec3& t,
    Direction& d1,
    Direction& d2,
    Mat36* dc1,
    Mat36* dc2)
{
    const Mat3 Rt = R.transpose();
    // The current point seen from the previous camera.
    const Vec3 rb = R * p.b[i];
    const Vec3 c = rb + t;
    // The previous point seen from the current camera.
    const Vec3 q = p.a[i] - t;
    const Vec3 e = Rt * q;
    if (c.z() < MIN_DEPTH || e.z() < MIN_DEPTH)
    {
        return false;
    }
    d1 = direction(p, p.b[i], c, R, p.proj_a[i]);
    d2 = direction(p, p.a[i], e, Rt, p.proj_b[i]);
    if (dc1)
    {
        dc1->leftCols<3>() = Mat3::Identity();
        dc1->rightCols<3>() = -skew(rb);
        dc2->leftCols<3>() = -Rt;
        dc2->rightCols<3>() = Rt * skew(q);
    }
    return true;
}

/** Robust cost of the whitened residuals at (R, t) and, if asked, the IRLS
 * Gauss-Newton system over [δt, w]. */
double cost(const Problem& p, const Mat3& R, const Vec3& t, Mat6* JtJ, Vec6* Jtr)
{
    if (JtJ)
    {
        JtJ->setZero();
        Jtr->setZero();
    }
    double rho = 0;
    Direction d[2];
    Mat36 dc[2];
    for (std::size_t i = 0; i < p.a.size(); ++i)
    {
        if (!directions(p, i, R, t, d[0], d[1], JtJ ? &dc[0] : nullptr, JtJ ? &dc[1] : nullptr))
        {
            continue;
        }
        for (int k = 0; k < 2; ++k)
        {
            const Eigen::LLT<Mat3> L(d[k].Sigma);
            if (L.info() != Eigen::Success)
            {
                continue;
            }
            const Vec3 r = L.matrixL().solve(d[k].r);
            // Huber per whitened coordinate: a wrong match is off in u and
            // v, not necessarily in its disparity.
            Vec3 w;
            for (int j = 0; j < 3; ++j)
            {
                rho += huber(std::abs(r[j]));
                w[j] = huberWeight(std::abs(r[j]));
            }
            if (JtJ)
            {
                const Mat36 J = L.matrixL().solve(d[k].P * dc[k]);
                *JtJ += J.transpose() * w.asDiagonal() * J;
                *Jtr += J.transpose() * w.cwiseProduct(r);
            }
        }
    }
    return rho;
}

double median(std::vector<double>& v)
{
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

/** Each image coordinate's measurement noise from the data (features are
 * located to a pixel or two across frames, disparities to a fraction of
 * one): every residual, divided by its predicted deviation, should have a
 * robust deviation (1.4826 MAD) of 1. Starts from the raw residuals' spread
 * (half of it: two measurements per residual) and rescales. */
void estimateNoise(Problem& p, const Mat3& R, const Vec3& t)
{
    p.sigma2 = Vec3(1, 1, 1);
    for (int iteration = 0; iteration < 4; ++iteration)
    {
        std::array<std::vector<double>, 3> z;
        Direction d[2];
        for (std::size_t i = 0; i < p.a.size(); ++i)
        {
            if (!directions(p, i, R, t, d[0], d[1], nullptr, nullptr))
            {
                continue;
            }
            for (const auto& dk : d)
            {
                for (int j = 0; j < 3; ++j)
                {
                    z[j].push_back(
                        iteration == 0 ? dk.r[j] * std::sqrt(0.5)
                                       : dk.r[j] / std::sqrt(dk.Sigma(j, j)));
                }
            }
        }
        Vec3 scale2;
        for (int j = 0; j < 3; ++j)
        {
            if (z[j].size() < 8)
            {
                return;
            }
            const double m = median(z[j]);
            for (double& x : z[j])
            {
                x = std::abs(x - m);
            }
            const double sd = 1.4826 * median(z[j]);
            if (!(sd > 1e-12))
            {
                return;  // an exact fit: keep what there is
            }
            scale2[j] = sd * sd;
        }
        p.sigma2 = p.sigma2.cwiseProduct(scale2);
    }
}
}  // namespace

StereoReprojectionRefinement::Result StereoReprojectionRefinement::refine(
    const std::vector<mrpt::math::TPoint3Df>& a,
    const std::vector<mrpt::math::TPoint3Df>& b,
    const mrpt::poses::CPose3D& T_prev_cur,
    double baseline,
    double focal_px,
    int max_iterations,
    double tolerance)
{
    Result res;
    res.T_prev_cur = T_prev_cur;
    Problem p;
    p.baseline = baseline;
    const std::size_t n = std::min(a.size(), b.size());
    for (std::size_t i = 0; i < n; ++i)
    {
        const Vec3 va(a[i].x, a[i].y, a[i].z), vb(b[i].x, b[i].y, b[i].z);
        if (!va.allFinite() || !vb.allFinite() || va.z() < MIN_DEPTH || vb.z() < MIN_DEPTH)
        {
            continue;
        }
        p.a.push_back(va);
        p.b.push_back(vb);
        p.proj_a.push_back(project(va, baseline));
        p.proj_b.push_back(project(vb, baseline));
    }
    res.pairs = p.a.size();
    if (p.a.size() < 4 || !(baseline > 0) || !std::isfinite(baseline))
    {
        return res;
    }
    Mat3 R;
    Vec3 t;
    detail::fromPose(T_prev_cur, R, t);
    const auto rms = [&]()
    {
        double ssr = 0;
        std::size_t n_res = 0;
        Direction d1, d2;
        for (std::size_t i = 0; i < p.a.size(); ++i)
        {
            if (directions(p, i, R, t, d1, d2, nullptr, nullptr))
            {
                ssr += d1.r.squaredNorm() + d2.r.squaredNorm();
                n_res += 6;
            }
        }
        return n_res ? focal_px * std::sqrt(ssr / double(n_res)) : 0.0;
    };
    res.rms_initial_px = rms();
    // Two rounds: the noise read at the start pose, then at the first fit.
    int evals = 0;
    for (int round = 0; round < 2; ++round)
    {
        estimateNoise(p, R, t);
        detail::levenbergMarquardt(
            [&p](const Mat3& Rc, const Vec3& tc, Mat6& H, Vec6& g) { cost(p, Rc, tc, &H, &g); },
            [&p](const Mat3& Rc, const Vec3& tc) { return cost(p, Rc, tc, nullptr, nullptr); }, R,
            t, cost(p, R, t, nullptr, nullptr), max_iterations, tolerance, evals);
    }
    res.evaluations = evals;
    res.rms_final_px = rms();
    res.T_prev_cur = detail::toPose(R, t);
    // Covariance: the whitened problem's (Jᵀ W J)⁻¹, twice, since both
    // directions read the same measurements.
    Mat6 JtJ;
    Vec6 Jtr;
    cost(p, R, t, &JtJ, &Jtr);
    const Eigen::LLT<Mat6> llt(JtJ);
    if (llt.info() == Eigen::Success)
    {
        Mat6 C = 2.0 * llt.solve(Mat6::Identity());
        // Left rotation vector w to the rectifier's right one, θ = Rᵀ w.
        Mat6 J = Mat6::Identity();
        J.block<3, 3>(3, 3) = R.transpose();
        C = J * C * J.transpose();
        if (C.allFinite())
        {
            for (int r = 0; r < 6; ++r)
            {
                for (int c = 0; c < 6; ++c)
                {
                    res.covariance(r, c) = 0.5 * (C(r, c) + C(c, r));
                }
            }
            res.has_covariance = true;
        }
    }
    return res;
}

}  // namespace emslam::egomotion
