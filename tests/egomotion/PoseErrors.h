// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Errors of an estimated action against the true one, for the pose tests.

#include <mrpt/poses/CPose3D.h>

#include <array>

namespace emslam::test
{
/** |t_err| of est ⊖ truth [m]. */
double translationError(const mrpt::poses::CPose3D& est, const mrpt::poses::CPose3D& truth);

/** Angle of est ⊖ truth [deg]. */
double rotationErrorDeg(const mrpt::poses::CPose3D& est, const mrpt::poses::CPose3D& truth);

/** truth − est in the parametrisation of the estimators' covariances:
 * [x, y, z] added, [θx, θy, θz] with R_truth = R_est exp(θ). */
std::array<double, 6> errorInCovarianceFrame(
    const mrpt::poses::CPose3D& est, const mrpt::poses::CPose3D& truth);

/** Accumulates errorInCovarianceFrame() and the predicted variances over
 * draws, and checks that the observed deviations lie in
 * [low, high] × the predicted ones, component by component. */
class CovarianceCheck
{
public:
    void add(
        const mrpt::poses::CPose3D& est,
        const mrpt::poses::CPose3D& truth,
        const mrpt::math::CMatrixDouble66& covariance);
    /** GoogleTest expectations; prints both deviations per component. */
    void expectWithin(double low, double high) const;

private:
    std::array<double, 6> m_empirical{}, m_predicted{};
    int m_draws{0};
};

}  // namespace emslam::test
