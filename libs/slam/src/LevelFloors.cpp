// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/LevelFloors.h>

#include <mrpt/core/bits_math.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace emslam::slam
{
namespace
{
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

double median(std::vector<double> v)
{
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// The median and the 99.73 % bulk of a χ²(2).
constexpr double CHI2_2DOF_MEDIAN = 1.386;
constexpr double CHI2_2DOF_GATE = 11.83;

Vec3 toEigen(const mrpt::math::TVector3D& v)
{
    return {v.x, v.y, v.z};
}

/** One measurement against the world up at the current poses. */
struct Disagreement
{
    std::size_t node{0};
    Eigen::Vector2d r;  // measured up (world, less the bias) minus the world up
    Eigen::Matrix2d C;  // the measurement's covariance, same plane
};

std::vector<Disagreement> disagreements(
    const emslam::rectify::PoseGraph& graph,
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals,
    std::size_t n)
{
    const auto& frame = graph.directionFrame();
    const Vec3 g = toEigen(frame.world);
    const Vec3 bias = toEigen(frame.bias);
    // Two directions across the world up: what a tilt changes.
    Eigen::Matrix<double, 3, 2> E;
    E.col(0) = g.unitOrthogonal();
    E.col(1) = g.cross(E.col(0));
    std::vector<Disagreement> out;
    for (std::size_t k = 0; k < n; ++k)
    {
        if (!verticals[k])
        {
            continue;
        }
        const auto& m = *verticals[k];
        const Mat3 R = graph.node(k).getRotationMatrix().asEigen();
        Disagreement d;
        d.node = k;
        d.r = E.transpose() * (R * (toEigen(m.up) - bias).normalized() - g);
        d.C = E.transpose() * R * m.covariance.asEigen() * R.transpose() * E;
        out.push_back(d);
    }
    return out;
}

/** How many neighbouring keyframes share one error: 1 + 2 Σ ρ_k of the
 * whitened disagreements in path order (summed while positive, up to 50
 * lags). Neighbours see much of the same floor, so their measurements are
 * not independent; their information is divided by this. */
double correlationTime(const std::vector<Disagreement>& dis)
{
    std::vector<Eigen::Vector2d> z;
    for (const auto& d : dis)
    {
        const Eigen::LLT<Eigen::Matrix2d> llt(d.C);
        if (llt.info() == Eigen::Success)
        {
            z.push_back(llt.matrixL().solve(d.r));
        }
    }
    if (z.size() < 10)
    {
        return 1;
    }
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& v : z)
    {
        mean += v;
    }
    mean /= static_cast<double>(z.size());
    double var = 0;
    for (const auto& v : z)
    {
        var += (v - mean).squaredNorm();
    }
    if (!(var > 0))
    {
        return 1;
    }
    double tau = 1;
    for (std::size_t lag = 1; lag <= 50 && lag < z.size() / 2; ++lag)
    {
        double c = 0;
        for (std::size_t i = 0; i + lag < z.size(); ++i)
        {
            c += (z[i] - mean).dot(z[i + lag] - mean);
        }
        const double rho = c / var;
        if (!(rho > 0))
        {
            break;
        }
        tau += 2 * rho;
    }
    return tau;
}
}  // namespace

LevelFloorsStats levelFloors(
    emslam::rectify::PoseGraph& graph,
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals,
    const std::vector<double>& tilt_variance,
    int passes)
{
    LevelFloorsStats stats;
    const std::size_t n = std::min(graph.nodeCount(), verticals.size());
    for (std::size_t k = 0; k < n; ++k)
    {
        stats.measured += verticals[k] ? 1 : 0;
    }
    if (stats.measured < 2)
    {
        return stats;
    }
    // Start: the world up is the mean of the measured ups, no bias.
    Vec3 sum = Vec3::Zero();
    for (std::size_t k = 0; k < n; ++k)
    {
        if (verticals[k])
        {
            sum += graph.node(k).getRotationMatrix().asEigen() * toEigen(verticals[k]->up);
        }
    }
    if (!(sum.norm() > 0) || !sum.allFinite())
    {
        return stats;
    }
    emslam::rectify::PoseGraph::DirectionFrame frame;
    const Vec3 g0 = sum.normalized();
    frame.world = {g0.x(), g0.y(), g0.z()};
    frame.solve_world = true;
    frame.solve_bias = true;
    graph.setDirectionFrame(frame);
    for (int pass = 0; pass < passes; ++pass)
    {
        const std::vector<Disagreement> dis = disagreements(graph, verticals, n);
        // The first pass gates by how far the egomotion may have tilted
        // each pose; later passes by the tilt spread the measurements show
        // beyond their own noise (by their median).
        double drift_var = 0;
        double correlation_time = 1;
        if (pass > 0)
        {
            correlation_time = correlationTime(dis);
            stats.correlation_time = correlation_time;
            std::vector<double> d2, var_m;
            for (const auto& d : dis)
            {
                d2.push_back(d.r.squaredNorm());
                var_m.push_back(0.5 * d.C.trace());
            }
            drift_var = std::max(0.0, median(d2) / CHI2_2DOF_MEDIAN / 2 - median(var_m));
            stats.drift_deg = mrpt::RAD2DEG(std::sqrt(drift_var));
        }
        graph.clearDirectionPriors();
        stats.used = 0;
        for (const auto& d : dis)
        {
            const double pose_var =
                pass == 0 ? (d.node < tilt_variance.size() ? tilt_variance[d.node] : 0.0)
                          : drift_var;
            const Eigen::Matrix2d S = d.C + pose_var * Eigen::Matrix2d::Identity();
            if (!(d.r.dot(S.ldlt().solve(d.r)) <= CHI2_2DOF_GATE))
            {
                continue;
            }
            ++stats.used;
            const auto& m = *verticals[d.node];
            mrpt::math::CMatrixDouble33 information = m.information();
            information.asEigen() /= correlation_time;
            graph.addDirectionPrior(d.node, m.up, information);
        }
        if (stats.used < 2)
        {
            graph.clearDirectionPriors();
            stats.used = 0;
            break;
        }
        // Far below any measurement's noise; a tighter stop only costs time.
        graph.optimize(8, 1, 1e-6);
    }
    stats.bias_deg = mrpt::RAD2DEG(toEigen(graph.directionFrame().bias).norm());
    return stats;
}

}  // namespace emslam::slam
