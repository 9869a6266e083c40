// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>

#include <mrpt/poses/Lie/SO.h>

#include <cmath>

namespace emslam::rectify
{
mrpt::poses::CPose3D planarAction(const mrpt::poses::CPose3D& action)
{
    const auto& R = action.getRotationMatrix();
    // R_y(θ) = [c 0 s; 0 1 0; -s 0 c]: θ from the entries of the XZ block.
    const double theta = std::atan2(R(0, 2) - R(2, 0), R(0, 0) + R(2, 2));
    mrpt::math::CVectorFixedDouble<3> w;
    w[0] = 0;
    w[1] = theta;
    w[2] = 0;
    mrpt::math::CVectorFixedDouble<3> t;
    t[0] = action.x();
    t[1] = 0;
    t[2] = action.z();
    return mrpt::poses::CPose3D::FromRotationAndTranslation(mrpt::poses::Lie::SO<3>::exp(w), t);
}

double rotationAngle(const mrpt::poses::CPose3D& T)
{
    const auto& R = T.getRotationMatrix();
    const double c = 0.5 * (R(0, 0) + R(1, 1) + R(2, 2) - 1.0);
    const double sx = R(2, 1) - R(1, 2), sy = R(0, 2) - R(2, 0), sz = R(1, 0) - R(0, 1);
    const double s = 0.5 * std::sqrt(sx * sx + sy * sy + sz * sz);
    return std::atan2(s, c);
}

mrpt::poses::CPose3D perturbAction(const mrpt::poses::CPose3D& action, const ActionDelta& delta)
{
    mrpt::math::CVectorFixedDouble<3> w;
    w[0] = delta[3];
    w[1] = delta[4];
    w[2] = delta[5];
    mrpt::math::CVectorFixedDouble<3> t;
    t[0] = action.x() + delta[0];
    t[1] = action.y() + delta[1];
    t[2] = action.z() + delta[2];
    const mrpt::math::CMatrixDouble33& A = action.getRotationMatrix();
    const mrpt::math::CMatrixDouble33 D = mrpt::poses::Lie::SO<3>::exp(w);
    mrpt::math::CMatrixDouble33 R;
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
        {
            R(r, c) = A(r, 0) * D(0, c) + A(r, 1) * D(1, c) + A(r, 2) * D(2, c);
        }
    }
    return mrpt::poses::CPose3D::FromRotationAndTranslation(R, t);
}

std::vector<mrpt::poses::CPose3D> actionsBetween(
    const std::vector<mrpt::poses::CPose3D>& element_poses)
{
    std::vector<mrpt::poses::CPose3D> actions;
    actions.reserve(element_poses.size());
    for (std::size_t i = 0; i < element_poses.size(); ++i)
    {
        actions.push_back(i == 0 ? element_poses[0] : element_poses[i] - element_poses[i - 1]);
    }
    return actions;
}

}  // namespace emslam::rectify
