// SPDX-License-Identifier: BSD-3-Clause
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
    const auto& R = d.getRotationMatrix();
    // Rotation angle from sin and cos: accurate for the small angles here.
    const double s = 0.5 * std::sqrt(
                               mrpt::square(R(2, 1) - R(1, 2)) + mrpt::square(R(0, 2) - R(2, 0)) +
                               mrpt::square(R(1, 0) - R(0, 1)));
    const double c = 0.5 * (R(0, 0) + R(1, 1) + R(2, 2) - 1.0);
    const double theta = std::atan2(s, c);
    const double n = static_cast<double>(std::max<std::size_t>(1, steps));
    const double sr = mrpt::DEG2RAD(sigma_rot_deg);
    const double t2 = mrpt::square(d.x()) + mrpt::square(d.y()) + mrpt::square(d.z());
    return 0.5 * weight * (t2 / (n * sigma_xyz * sigma_xyz) + theta * theta / (n * sr * sr));
}

}  // namespace emslam::rectify
