// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/rectify/OdometryPrior.h>

#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>

namespace emslam::rectify
{
double OdometryPrior::cost(
    const mrpt::poses::CPose3D& action,
    const mrpt::poses::CPose3D& reference,
    std::size_t steps) const
{
    if (!enabled())
    {
        return 0.0;
    }
    const mrpt::poses::CPose3D d = action - reference;  // reference⁻¹ ⊕ action
    const double theta = rotationAngle(d);
    const double n = static_cast<double>(std::max<std::size_t>(1, steps));
    const double sr = mrpt::DEG2RAD(sigma_rot_deg);
    const double t2 = mrpt::square(d.x()) + mrpt::square(d.y()) + mrpt::square(d.z());
    return 0.5 * weight * (t2 / (n * sigma_xyz * sigma_xyz) + theta * theta / (n * sr * sr));
}

double OdometryPrior::cost(
    const mrpt::poses::CPose3D& action,
    const mrpt::poses::CPose3D& reference,
    const ActionCovariance& information) const
{
    if (!enabled())
    {
        return 0.0;
    }
    return weight * halfMahalanobis(actionDifference(action, reference), information);
}

ActionCovariance OdometryPrior::stepCovariance() const
{
    return diagonalCovariance(sigma_xyz, mrpt::DEG2RAD(sigma_rot_deg));
}

std::string toString(PriorCovariance c)
{
    return c == PriorCovariance::Egomotion ? "egomotion" : "fixed";
}

}  // namespace emslam::rectify
