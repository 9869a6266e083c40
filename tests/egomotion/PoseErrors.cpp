// SPDX-License-Identifier: BSD-3-Clause
#include "PoseErrors.h"

#include <mrpt/poses/Lie/SO.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace emslam::test
{
double translationError(const mrpt::poses::CPose3D& est, const mrpt::poses::CPose3D& truth)
{
    return (est - truth).norm();
}

double rotationErrorDeg(const mrpt::poses::CPose3D& est, const mrpt::poses::CPose3D& truth)
{
    const auto d = (est - truth).getRotationMatrix();
    const double c = std::clamp((d.trace() - 1) / 2, -1.0, 1.0);
    return std::acos(c) * 180 / M_PI;
}

std::array<double, 6> errorInCovarianceFrame(
    const mrpt::poses::CPose3D& est, const mrpt::poses::CPose3D& truth)
{
    // R_est⁻¹ R_truth is the rotation of truth ⊖ est.
    const auto w = mrpt::poses::Lie::SO<3>::log((truth - est).getRotationMatrix());
    return {truth.x() - est.x(), truth.y() - est.y(), truth.z() - est.z(), w[0], w[1], w[2]};
}

void CovarianceCheck::add(
    const mrpt::poses::CPose3D& est,
    const mrpt::poses::CPose3D& truth,
    const mrpt::math::CMatrixDouble66& covariance)
{
    const auto e = errorInCovarianceFrame(est, truth);
    for (int k = 0; k < 6; ++k)
    {
        m_empirical[k] += e[k] * e[k];
        m_predicted[k] += covariance(k, k);
    }
    ++m_draws;
}

void CovarianceCheck::expectWithin(double low, double high) const
{
    ASSERT_GT(m_draws, 0);
    for (int k = 0; k < 6; ++k)
    {
        const double empirical_sd = std::sqrt(m_empirical[k] / m_draws);
        const double predicted_sd = std::sqrt(m_predicted[k] / m_draws);
        std::printf(
            "component %d: empirical sd %.5f, predicted sd %.5f\n", k, empirical_sd, predicted_sd);
        EXPECT_LT(empirical_sd, high * predicted_sd) << "component " << k;
        EXPECT_GT(empirical_sd, low * predicted_sd) << "component " << k;
    }
}

}  // namespace emslam::test
