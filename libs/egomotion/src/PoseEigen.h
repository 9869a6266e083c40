// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: the pose estimators work on Eigen rotations and translations.

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>

namespace emslam::egomotion::detail
{
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/** Rotation matrix of a rotation vector (first order below 1e-12 rad). */
inline Mat3 expSO3(const Vec3& w)
{
    const double th = w.norm();
    if (th < 1e-12)
    {
        Mat3 r = Mat3::Identity();
        r(0, 1) = -w.z();
        r(0, 2) = w.y();
        r(1, 0) = w.z();
        r(1, 2) = -w.x();
        r(2, 0) = -w.y();
        r(2, 1) = w.x();
        return r;
    }
    return Eigen::AngleAxisd(th, w / th).toRotationMatrix();
}

inline void fromPose(const mrpt::poses::CPose3D& T, Mat3& R, Vec3& t)
{
    const auto Rm = T.getRotationMatrix();
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
        {
            R(r, c) = Rm(r, c);
        }
    }
    t = Vec3(T.x(), T.y(), T.z());
}

inline mrpt::poses::CPose3D toPose(const Mat3& R, const Vec3& t)
{
    mrpt::math::CMatrixDouble44 H = mrpt::math::CMatrixDouble44::Identity();
    // Re-orthonormalise: many small left-multiplied updates accumulate
    // rounding.
    const Eigen::Quaterniond q(R);
    const Mat3 Rn = q.normalized().toRotationMatrix();
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
        {
            H(r, c) = Rn(r, c);
        }
        H(r, 3) = t[r];
    }
    return mrpt::poses::CPose3D::FromHomogeneousMatrix(H);
}

/** Levenberg-Marquardt on a pose from (R, t) with energy `e`:
 * `system(R, t, H, g)` fills the Gauss-Newton Hessian H and the gradient g
 * of the energy over [δt, w] (R ← exp(w) R, t ← t + δt), `energy(R, t)`
 * evaluates it. δ = −(H + λ diag H)⁻¹ g, kept only when the energy drops;
 * stops when it drops by less than `tolerance` (relative). Counts the
 * evaluations in `evals`; returns the final energy. */
template <class System, class Energy>
double levenbergMarquardt(
    const System& system,
    const Energy& energy,
    Mat3& R,
    Vec3& t,
    double e,
    int max_iterations,
    double tolerance,
    int& evals)
{
    double lambda = 1e-4;
    for (int it = 0; it < max_iterations; ++it)
    {
        Mat6 H;
        Vec6 g;
        system(R, t, H, g);
        ++evals;
        bool moved = false;
        double gain = 0;
        for (int k = 0; k < 12 && !moved; ++k)
        {
            Mat6 A = H;
            A.diagonal() *= 1.0 + lambda;
            const Vec6 d = A.ldlt().solve(-g);
            if (!d.allFinite())
            {
                break;
            }
            const Mat3 R2 = expSO3(d.tail<3>()) * R;
            const Vec3 t2 = t + d.head<3>();
            const double e2 = energy(R2, t2);
            ++evals;
            if (e2 < e)
            {
                R = R2;
                t = t2;
                gain = e - e2;
                e = e2;
                lambda = std::max(lambda * 0.1, 1e-9);
                moved = true;
            }
            else
            {
                lambda *= 10.0;
            }
        }
        if (!moved || gain <= tolerance * std::max(e, 1e-300))
        {
            break;
        }
    }
    return e;
}

}  // namespace emslam::egomotion::detail
