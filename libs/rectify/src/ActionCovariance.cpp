// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/ActionCovariance.h>

#include <mrpt/poses/Lie/SO.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

namespace emslam::rectify
{
namespace
{
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;

Mat3 rotationOf(const mrpt::poses::CPose3D& T)
{
    Mat3 R;
    const auto& m = T.getRotationMatrix();
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
        {
            R(r, c) = m(r, c);
        }
    }
    return R;
}

Mat3 skew(double x, double y, double z)
{
    Mat3 s;
    s << 0, -z, y, z, 0, -x, -y, x, 0;
    return s;
}

Mat6 toEigen(const ActionCovariance& c)
{
    Mat6 m;
    for (int r = 0; r < 6; ++r)
    {
        for (int k = 0; k < 6; ++k)
        {
            m(r, k) = c(r, k);
        }
    }
    return m;
}

ActionCovariance fromEigen(const Mat6& m)
{
    ActionCovariance c;
    for (int r = 0; r < 6; ++r)
    {
        for (int k = 0; k < 6; ++k)
        {
            c(r, k) = 0.5 * (m(r, k) + m(k, r));  // keep it exactly symmetric
        }
    }
    return c;
}

/** The components a dof keeps: 3DOF is [δx, δz, δθy]. */
std::array<bool, 6> keptComponents(int dof)
{
    if (dof == 3)
    {
        return {true, false, true, false, true, false};
    }
    return {true, true, true, true, true, true};
}
}  // namespace

ActionDelta actionDifference(
    const mrpt::poses::CPose3D& action, const mrpt::poses::CPose3D& reference)
{
    const Mat3 D = rotationOf(reference).transpose() * rotationOf(action);
    mrpt::math::CMatrixDouble33 Dm;
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
        {
            Dm(r, c) = D(r, c);
        }
    }
    const auto w = mrpt::poses::Lie::SO<3>::log(Dm);
    return {
        action.x() - reference.x(),
        action.y() - reference.y(),
        action.z() - reference.z(),
        w[0],
        w[1],
        w[2]};
}

ActionCovariance composeCovariance(
    const mrpt::poses::CPose3D& a1,
    const ActionCovariance& c1,
    const mrpt::poses::CPose3D& a2,
    const ActionCovariance& c2)
{
    // a = a1 ⊕ a2: R = R1 R2, t = t1 + R1 t2. A change (δt1, θ1) of a1 moves
    // t by δt1 − R1 [t2]× θ1 and turns R by R2ᵀ θ1 on the right; a change
    // (δt2, θ2) of a2 moves t by R1 δt2 and turns R by θ2.
    const Mat3 R1 = rotationOf(a1), R2 = rotationOf(a2);
    Mat6 J1 = Mat6::Zero(), J2 = Mat6::Zero();
    J1.block<3, 3>(0, 0) = Mat3::Identity();
    J1.block<3, 3>(0, 3) = -R1 * skew(a2.x(), a2.y(), a2.z());
    J1.block<3, 3>(3, 3) = R2.transpose();
    J2.block<3, 3>(0, 0) = R1;
    J2.block<3, 3>(3, 3) = Mat3::Identity();
    return fromEigen(J1 * toEigen(c1) * J1.transpose() + J2 * toEigen(c2) * J2.transpose());
}

ActionCovariance transportCovariance(const mrpt::poses::CPose3D& fixed, const ActionCovariance& c2)
{
    Mat6 J2 = Mat6::Identity();
    J2.block<3, 3>(0, 0) = rotationOf(fixed);
    return fromEigen(J2 * toEigen(c2) * J2.transpose());
}

ActionCovariance diagonalCovariance(double sigma_xyz, double sigma_rot_rad)
{
    ActionCovariance c;
    c.setZero();
    for (int k = 0; k < 3; ++k)
    {
        c(k, k) = sigma_xyz * sigma_xyz;
        c(k + 3, k + 3) = sigma_rot_rad * sigma_rot_rad;
    }
    return c;
}

ActionCovariance predictionCovariance(
    const mrpt::poses::CPose3D& predicted, double min_sigma_xyz, double min_sigma_rot_rad)
{
    const double t = std::sqrt(
        predicted.x() * predicted.x() + predicted.y() * predicted.y() +
        predicted.z() * predicted.z());
    return diagonalCovariance(
        std::max(t, min_sigma_xyz), std::max(rotationAngle(predicted), min_sigma_rot_rad));
}

ActionCovariance planarCovariance(const ActionCovariance& c)
{
    const auto keep = keptComponents(3);
    ActionCovariance p;
    p.setZero();
    for (int r = 0; r < 6; ++r)
    {
        for (int k = 0; k < 6; ++k)
        {
            if (keep[r] && keep[k])
            {
                p(r, k) = c(r, k);
            }
        }
    }
    return p;
}

ActionCovariance informationOf(const ActionCovariance& c, int dof, double min_variance)
{
    const auto keep = keptComponents(dof);
    int idx[6];
    int n = 0;
    for (int k = 0; k < 6; ++k)
    {
        if (keep[k])
        {
            idx[n++] = k;
        }
    }
    Eigen::MatrixXd m(n, n);
    for (int r = 0; r < n; ++r)
    {
        for (int k = 0; k < n; ++k)
        {
            m(r, k) = c(idx[r], idx[k]);
        }
        m(r, r) = std::max(m(r, r), min_variance);
    }
    Eigen::MatrixXd inv = m.ldlt().solve(Eigen::MatrixXd::Identity(n, n));
    ActionCovariance out;
    out.setZero();
    if (!inv.allFinite())
    {
        return out;  // no information rather than an infinite weight
    }
    for (int r = 0; r < n; ++r)
    {
        for (int k = 0; k < n; ++k)
        {
            out(idx[r], idx[k]) = 0.5 * (inv(r, k) + inv(k, r));
        }
    }
    return out;
}

double halfMahalanobis(const ActionDelta& delta, const ActionCovariance& information)
{
    double s = 0;
    for (int r = 0; r < 6; ++r)
    {
        double row = 0;
        for (int k = 0; k < 6; ++k)
        {
            row += information(r, k) * delta[static_cast<std::size_t>(k)];
        }
        s += delta[static_cast<std::size_t>(r)] * row;
    }
    return 0.5 * s;
}

}  // namespace emslam::rectify
