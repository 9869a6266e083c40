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
// The same bulk of a χ²(4): the world up and the bias, two each.
constexpr double CHI2_4DOF_GATE = 16.25;

Vec3 toEigen(const mrpt::math::TVector3D& v)
{
    return {v.x, v.y, v.z};
}

/** Two unit directions across `n`. */
Eigen::Matrix<double, 3, 2> across(const Vec3& n)
{
    Eigen::Matrix<double, 3, 2> E;
    E.col(0) = n.unitOrthogonal();
    E.col(1) = n.cross(E.col(0));
    return E;
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
    const Eigen::Matrix<double, 3, 2> E = across(g);
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

/** The smallest eigenvalue of the information the graph's direction priors
 * give on the bias (in the plane across their mean direction, node frame)
 * with the world up marginalised, at the graph's poses [rad⁻²]. Zero when
 * every prior sees the world up from the same camera orientation: then
 * b and w move together. */
double biasInformation(const emslam::rectify::PoseGraph& graph)
{
    const auto& priors = graph.directionPriors();
    Vec3 mean = Vec3::Zero();
    for (const auto& p : priors)
    {
        mean += toEigen(p.in_node);
    }
    if (!(mean.norm() > 0))
    {
        return 0;
    }
    const auto& frame = graph.directionFrame();
    const Vec3 b = toEigen(frame.bias);
    const Eigen::Matrix<double, 3, 2> Eb = across(mean.normalized());
    const Eigen::Matrix<double, 3, 2> Ew = across(toEigen(frame.world));
    Eigen::Matrix2d Ibb = Eigen::Matrix2d::Zero(), Ibw = Eigen::Matrix2d::Zero(),
                    Iww = Eigen::Matrix2d::Zero();
    for (const auto& p : priors)
    {
        // ρ = normalize(u − b) − Rᵀ w, linearised in b and in w.
        const Vec3 d = toEigen(p.in_node) - b;
        const Vec3 n = d.normalized();
        const Eigen::Matrix<double, 3, 2> Jb =
            -(Mat3::Identity() - n * n.transpose()) * Eb / d.norm();
        const Mat3 R = graph.node(p.node).getRotationMatrix().asEigen();
        const Eigen::Matrix<double, 3, 2> Jw = -R.transpose() * Ew;
        const Mat3 L = p.information.asEigen();
        Ibb += Jb.transpose() * L * Jb;
        Ibw += Jb.transpose() * L * Jw;
        Iww += Jw.transpose() * L * Jw;
    }
    const Eigen::LDLT<Eigen::Matrix2d> ww(Iww);
    if (ww.info() != Eigen::Success || !(Iww.determinant() > 0))
    {
        return 0;
    }
    const Eigen::Matrix2d S = Ibb - Ibw * ww.solve(Ibw.transpose());
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(0.5 * (S + S.transpose()))
        .eigenvalues()
        .minCoeff();
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
/** Starts the world up at the mean measured up (no bias); false if there
 * is none. */
bool startWorldUp(
    emslam::rectify::PoseGraph& graph,
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals,
    std::size_t n,
    double max_bias)
{
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
        return false;
    }
    emslam::rectify::PoseGraph::DirectionFrame frame;
    const Vec3 g0 = sum.normalized();
    frame.world = {g0.x(), g0.y(), g0.z()};
    frame.solve_world = true;
    frame.max_bias = max_bias;
    graph.setDirectionFrame(frame);
    return true;
}

/** One pass's gate: the measurements that agree with the world up at the
 * current poses replace the graph's priors; those of nodes before
 * `regate_from` keep their decision (and prior). A measurement's pose may be
 * tilted by `pose_variance[k]` (nothing: 0) and, with `spread`, by the
 * spread the measurements show beyond their own noise (by their median);
 * with `spread` the measurements' information is also divided by their
 * correlation time. Returns false (and no priors) if fewer than two agree. */
bool gateVerticals(
    emslam::rectify::PoseGraph& graph,
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals,
    std::size_t n,
    const std::vector<double>& pose_variance,
    bool spread,
    LevelFloorsStats& stats,
    std::size_t regate_from = 0)
{
    const std::vector<emslam::rectify::PoseGraph::DirectionPrior> before = graph.directionPriors();
    const std::vector<Disagreement> dis = disagreements(graph, verticals, n);
    double drift_var = 0;
    double correlation_time = 1;
    if (spread && !dis.empty())
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
    for (const auto& p : before)
    {
        if (p.node < regate_from)
        {
            graph.addDirectionPrior(p.node, p.in_node, p.information);
            ++stats.used;
        }
    }
    for (const auto& d : dis)
    {
        if (d.node < regate_from)
        {
            continue;
        }
        const double pose_var =
            drift_var + (d.node < pose_variance.size() ? pose_variance[d.node] : 0.0);
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
        return false;
    }
    return true;
}

/** The bias is an unknown only while the graph's priors observe it (the
 * data pin it to a third of its bound, 3 σ within it); otherwise zero. */
void decideBias(emslam::rectify::PoseGraph& graph, double max_bias)
{
    const double min_bias_information = max_bias > 0 ? std::pow(3 / max_bias, 2) : 0.0;
    auto f = graph.directionFrame();
    f.solve_bias = max_bias > 0 && biasInformation(graph) >= min_bias_information;
    if (!f.solve_bias)
    {
        f.bias = {0, 0, 0};
    }
    graph.setDirectionFrame(f);
}

void reportBias(const emslam::rectify::PoseGraph& graph, LevelFloorsStats& stats)
{
    stats.bias_observable = graph.directionFrame().solve_bias;
    if (stats.bias_observable)
    {
        stats.bias_deg = mrpt::RAD2DEG(toEigen(graph.directionFrame().bias).norm());
    }
}

std::size_t countMeasured(
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals, std::size_t n)
{
    std::size_t c = 0;
    for (std::size_t k = 0; k < n; ++k)
    {
        c += verticals[k] ? 1 : 0;
    }
    return c;
}
}  // namespace

LevelFloorsStats levelFloors(
    emslam::rectify::PoseGraph& graph,
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals,
    const std::vector<double>& tilt_variance,
    int passes,
    double max_bias)
{
    LevelFloorsStats stats;
    const std::size_t n = std::min(graph.nodeCount(), verticals.size());
    stats.measured = countMeasured(verticals, n);
    if (stats.measured < 2 || !startWorldUp(graph, verticals, n, max_bias))
    {
        return stats;
    }
    for (int pass = 0; pass < passes; ++pass)
    {
        // The first pass gates by how far the egomotion may have tilted
        // each pose; later passes by the tilt spread the measurements show
        // beyond their own noise (by their median).
        const bool gated = pass == 0
                               ? gateVerticals(graph, verticals, n, tilt_variance, false, stats)
                               : gateVerticals(graph, verticals, n, {}, true, stats);
        if (!gated)
        {
            break;
        }
        decideBias(graph, max_bias);
        // Far below any measurement's noise; a tighter stop only costs time.
        graph.optimize(8, 1, 1e-6);
    }
    reportBias(graph, stats);
    return stats;
}

LevelFloorsStats relevelFloors(
    emslam::rectify::PoseGraph& graph,
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals,
    const std::vector<double>& pose_tilt_variance,
    const emslam::rectify::PoseGraph::DirectionFrame& levelled_for,
    std::size_t regate_from,
    double max_bias)
{
    LevelFloorsStats stats;
    const std::size_t n = std::min(graph.nodeCount(), verticals.size());
    stats.measured = countMeasured(verticals, n);
    stats.first_changed = graph.nodeCount();
    if (stats.measured < 2)
    {
        return stats;
    }
    std::vector<bool> had_prior(graph.nodeCount(), false);
    for (const auto& p : graph.directionPriors())
    {
        had_prior[p.node] = true;
    }
    if (graph.directionPriors().empty() && !startWorldUp(graph, verticals, n, max_bias))
    {
        return stats;
    }
    const auto solveShared = [&]
    {
        decideBias(graph, max_bias);
        // Every node held: the world up and the bias only.
        graph.optimize(8, graph.nodeCount(), 1e-9);
        reportBias(graph, stats);
    };
    bool gated = gateVerticals(graph, verticals, n, pose_tilt_variance, true, stats, regate_from);
    if (gated)
    {
        solveShared();
    }
    // What the next solve must free: a node whose prior came or went, and
    // every node once the world up and bias have moved beyond their own
    // noise since `levelled_for` (what the priors would gain, at the held
    // poses, is beyond the bulk of a χ² of those four unknowns): a bias
    // found only after the first turns must level what came before it.
    std::vector<bool> has_prior(graph.nodeCount(), false);
    for (const auto& p : graph.directionPriors())
    {
        has_prior[p.node] = true;
    }
    for (std::size_t k = 1; k < graph.nodeCount(); ++k)
    {
        if (had_prior[k] != has_prior[k])
        {
            stats.first_changed = k;
            break;
        }
    }
    if (gated)
    {
        const Vec3 w0 = toEigen(levelled_for.world), b0 = toEigen(levelled_for.bias);
        double gain = 0;
        for (const auto& p : graph.directionPriors())
        {
            const Vec3 r = (toEigen(p.in_node) - b0).normalized() -
                           graph.node(p.node).getRotationMatrix().asEigen().transpose() * w0;
            gain += 0.5 * r.dot(p.information.asEigen() * r) - graph.priorCost(p);
        }
        if (gain > CHI2_4DOF_GATE / 2)
        {
            // Every node is solved again: every up is gated again.
            stats.first_changed = 1;
            if (regate_from > 0)
            {
                gated = gateVerticals(graph, verticals, n, pose_tilt_variance, true, stats);
                if (gated)
                {
                    solveShared();
                }
            }
        }
    }
    return stats;
}

}  // namespace emslam::slam
