// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/PoseMean.h>

#include <mrpt/math/CQuaternion.h>

#include <cmath>
#include <stdexcept>

namespace emslam::rectify
{
mrpt::poses::CPose3D meanPose(const std::vector<mrpt::poses::CPose3D>& poses)
{
    if (poses.empty())
    {
        throw std::invalid_argument("meanPose(): no poses");
    }
    double t[3] = {0, 0, 0};
    double q_sum[4] = {0, 0, 0, 0};
    mrpt::math::CQuaternionDouble first;
    poses.front().getAsQuaternion(first);
    for (const auto& p : poses)
    {
        t[0] += p.x();
        t[1] += p.y();
        t[2] += p.z();
        mrpt::math::CQuaternionDouble q;
        p.getAsQuaternion(q);
        // q and -q are the same rotation: sum them on one hemisphere.
        const double dot =
            q.r() * first.r() + q.x() * first.x() + q.y() * first.y() + q.z() * first.z();
        const double sign = dot < 0 ? -1.0 : 1.0;
        q_sum[0] += sign * q.r();
        q_sum[1] += sign * q.x();
        q_sum[2] += sign * q.y();
        q_sum[3] += sign * q.z();
    }
    const double n = static_cast<double>(poses.size());
    // The sum cannot vanish: every term has a non-negative dot with `first`.
    const double norm = std::sqrt(
        q_sum[0] * q_sum[0] + q_sum[1] * q_sum[1] + q_sum[2] * q_sum[2] + q_sum[3] * q_sum[3]);
    const mrpt::math::CQuaternionDouble mean(
        q_sum[0] / norm, q_sum[1] / norm, q_sum[2] / norm, q_sum[3] / norm);
    return mrpt::poses::CPose3D(mean, t[0] / n, t[1] / n, t[2] / n);
}

}  // namespace emslam::rectify
