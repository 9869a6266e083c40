// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/rectify/PoseGraph.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace emslam::rectify
{
namespace
{
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat6x12 = Eigen::Matrix<double, 6, 12>;

Vec6 toVec(const ActionDelta& d)
{
    Vec6 v;
    for (int k = 0; k < 6; ++k)
    {
        v[k] = d[static_cast<std::size_t>(k)];
    }
    return v;
}

Mat6 toMat(const ActionCovariance& m)
{
    Mat6 r;
    for (int a = 0; a < 6; ++a)
    {
        for (int b = 0; b < 6; ++b)
        {
            r(a, b) = m(a, b);
        }
    }
    return r;
}

Vec6 residual(
    const mrpt::poses::CPose3D& xi, const mrpt::poses::CPose3D& xj, const mrpt::poses::CPose3D& z)
{
    return toVec(actionDifference(xj - xi, z));
}

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat32 = Eigen::Matrix<double, 3, 2>;

Vec3 toVec3(const mrpt::math::TVector3D& v)
{
    return {v.x, v.y, v.z};
}

/** Two unit vectors orthogonal to unit `n` and to each other. */
Mat32 tangentBasis(const Vec3& n)
{
    Mat32 E;
    E << n.unitOrthogonal(), n.cross(n.unitOrthogonal());
    return E;
}

/** ρ = normalize(u − b) − Rᵀ w, in the node's frame. */
Vec3 priorResidual(
    const mrpt::poses::CPose3D& x, const PoseGraph::DirectionPrior& p, const Vec3& w, const Vec3& b)
{
    return (toVec3(p.in_node) - b).normalized() - x.getRotationMatrix().asEigen().transpose() * w;
}

Mat3 skew(const Vec3& v)
{
    Mat3 m;
    m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return m;
}

/** d residual / d (δ_i, δ_j) of an edge, in closed form, for the moves
 * x ← perturbAction(x, δ) (translation added in the world, rotation
 * R·exp(w)): with t = R_iᵀ(t_j − t_i), R = R_iᵀR_j and φ the rotation part
 * of the residual (log of R_zᵀR), Jr⁻¹ the inverse right Jacobian of SO(3),
 *   ∂t/∂t_i = −R_iᵀ, ∂t/∂w_i = [t]×, ∂t/∂t_j = R_iᵀ,
 *   ∂φ/∂w_i = −Jr⁻¹(φ) Rᵀ, ∂φ/∂w_j = Jr⁻¹(φ).
 * Why: central differences cost 24 residuals per edge and were most of a
 * solve of a long run's graph. */
Mat6x12 edgeJacobian(const mrpt::poses::CPose3D& xi, const mrpt::poses::CPose3D& xj, const Vec6& r)
{
    const Mat3 Ri = xi.getRotationMatrix().asEigen();
    const Mat3 Rj = xj.getRotationMatrix().asEigen();
    const Vec3 t = Ri.transpose() * Vec3(xj.x() - xi.x(), xj.y() - xi.y(), xj.z() - xi.z());
    const Mat3 R = Ri.transpose() * Rj;
    const Vec3 phi = r.tail<3>();
    const double theta = phi.norm();
    const Mat3 P = skew(phi);
    // 1/θ² − (1 + cos θ) / (2 θ sin θ), → 1/12 for small θ.
    const double c = theta < 1e-4 ? 1.0 / 12.0
                                  : 1.0 / (theta * theta) -
                                        (1 + std::cos(theta)) / (2 * theta * std::sin(theta));
    const Mat3 JrInv = Mat3::Identity() + 0.5 * P + c * P * P;
    Mat6x12 J = Mat6x12::Zero();
    J.block<3, 3>(0, 0) = -Ri.transpose();
    J.block<3, 3>(0, 3) = skew(t);
    J.block<3, 3>(3, 3) = -JrInv * R.transpose();
    J.block<3, 3>(0, 6) = Ri.transpose();
    J.block<3, 3>(3, 9) = JrInv;
    return J;
}

mrpt::poses::CPose3D moved(const mrpt::poses::CPose3D& x, const Vec6& d)
{
    return perturbAction(x, {d[0], d[1], d[2], d[3], d[4], d[5]});
}
}  // namespace

std::size_t PoseGraph::addNode(const mrpt::poses::CPose3D& pose)
{
    m_nodes.push_back(pose);
    return m_nodes.size() - 1;
}

void PoseGraph::addEdge(
    std::size_t from,
    std::size_t to,
    const mrpt::poses::CPose3D& measurement,
    const ActionCovariance& covariance,
    std::size_t tag)
{
    if (from >= m_nodes.size() || to >= m_nodes.size())
    {
        throw std::out_of_range(
            "PoseGraph::addEdge: node " + std::to_string(std::max(from, to)) + " of " +
            std::to_string(m_nodes.size()));
    }
    if (from == to)
    {
        throw std::invalid_argument("PoseGraph::addEdge: an edge needs two different nodes");
    }
    m_edges.push_back({from, to, measurement, informationOf(covariance, 6), tag});
}

std::size_t PoseGraph::removeEdgesIf(const std::function<bool(const Edge&)>& drop)
{
    const std::size_t before = m_edges.size();
    m_edges.erase(std::remove_if(m_edges.begin(), m_edges.end(), drop), m_edges.end());
    return before - m_edges.size();
}

void PoseGraph::setEdgeMeasurement(std::size_t index, const mrpt::poses::CPose3D& measurement)
{
    m_edges.at(index).measurement = measurement;
}

void PoseGraph::setNode(std::size_t index, const mrpt::poses::CPose3D& pose)
{
    m_nodes.at(index) = pose;
}

void PoseGraph::addDirectionPrior(
    std::size_t node,
    const mrpt::math::TVector3D& in_node,
    const mrpt::math::CMatrixDouble33& information)
{
    if (node >= m_nodes.size())
    {
        throw std::out_of_range(
            "PoseGraph::addDirectionPrior: node " + std::to_string(node) + " of " +
            std::to_string(m_nodes.size()));
    }
    m_priors.push_back({node, in_node, information});
}

double PoseGraph::priorCost(const DirectionPrior& p) const
{
    const Vec3 r = priorResidual(m_nodes[p.node], p, toVec3(m_frame.world), toVec3(m_frame.bias));
    return 0.5 * r.dot(p.information.asEigen() * r);
}

double PoseGraph::edgeCost(const Edge& e) const
{
    const Vec6 r = residual(m_nodes[e.from], m_nodes[e.to], e.measurement);
    return 0.5 * r.dot(toMat(e.information) * r);
}

double PoseGraph::cost() const
{
    double c = 0;
    for (const auto& e : m_edges)
    {
        c += edgeCost(e);
    }
    for (const auto& p : m_priors)
    {
        c += priorCost(p);
    }
    return c;
}

PoseGraph::Result PoseGraph::optimize(
    int max_iterations, std::size_t first_free, double min_relative_decrease)
{
    const std::size_t n = m_nodes.size();
    first_free = std::min(std::max<std::size_t>(first_free, 1), n);
    // Only the edges that reach a free node change the cost.
    std::vector<std::size_t> active;
    for (std::size_t e = 0; e < m_edges.size(); ++e)
    {
        if (m_edges[e].from >= first_free || m_edges[e].to >= first_free)
        {
            active.push_back(e);
        }
    }
    // Nodes before first_free are fixed (node 0 always: the world): the
    // unknowns are the others, six each, then the shared world direction
    // and bias of the direction priors (two each). The priors of fixed
    // nodes pull on those two only: without them, they change nothing.
    const bool any_prior = !m_priors.empty();
    const bool shared_unknowns = any_prior && (m_frame.solve_world || m_frame.solve_bias);
    std::vector<const DirectionPrior*> active_priors;
    for (const auto& p : m_priors)
    {
        if (shared_unknowns || p.node >= first_free)
        {
            active_priors.push_back(&p);
        }
    }
    const auto activeCost = [&]
    {
        double c = 0;
        for (std::size_t e : active)
        {
            c += edgeCost(m_edges[e]);
        }
        for (const DirectionPrior* p : active_priors)
        {
            c += priorCost(*p);
        }
        return c;
    };
    Result res;
    res.initial_cost = activeCost();
    res.final_cost = res.initial_cost;
    if ((first_free >= n || active.empty()) && active_priors.empty())
    {
        return res;
    }
    const auto world_col = static_cast<Eigen::Index>(6 * (n - first_free));
    const Eigen::Index bias_col = world_col + (any_prior && m_frame.solve_world ? 2 : 0);
    const Eigen::Index dim = bias_col + (any_prior && m_frame.solve_bias ? 2 : 0);
    // The bias moves orthogonally to the mean measured direction.
    Vec3 mean_measured = Vec3::Zero();
    for (const auto& p : m_priors)
    {
        mean_measured += toVec3(p.in_node);
    }
    const Mat32 Eb =
        tangentBasis(mean_measured.norm() > 0 ? mean_measured.normalized() : Vec3::UnitY());
    const auto col = [first_free](std::size_t node)
    { return static_cast<Eigen::Index>(6 * (node - first_free)); };
    const auto fixed = [first_free](std::size_t node) { return node < first_free; };
    double lambda = 1e-4;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
    bool analysed = false;
    constexpr double h = 1e-6;  // central differences of a smooth residual
    for (int it = 0; it < max_iterations; ++it)
    {
        std::vector<Eigen::Triplet<double>> triplets;
        triplets.reserve(active.size() * 144);
        Eigen::VectorXd g = Eigen::VectorXd::Zero(dim);
        for (std::size_t ei : active)
        {
            const Edge& e = m_edges[ei];
            const auto& xi = m_nodes[e.from];
            const auto& xj = m_nodes[e.to];
            const Vec6 r = residual(xi, xj, e.measurement);
            const Mat6x12 J = edgeJacobian(xi, xj, r);
            const Mat6 W = toMat(e.information);
            const Eigen::Matrix<double, 12, 12> H = J.transpose() * W * J;
            const Eigen::Matrix<double, 12, 1> b = J.transpose() * W * r;
            const std::size_t ends[2] = {e.from, e.to};
            for (int a = 0; a < 2; ++a)
            {
                if (fixed(ends[a]))
                {
                    continue;
                }
                g.segment<6>(col(ends[a])) += b.segment<6>(6 * a);
                for (int c = 0; c < 2; ++c)
                {
                    if (fixed(ends[c]))
                    {
                        continue;
                    }
                    for (int p = 0; p < 6; ++p)
                    {
                        for (int q = 0; q < 6; ++q)
                        {
                            triplets.emplace_back(
                                col(ends[a]) + p, col(ends[c]) + q, H(6 * a + p, 6 * c + q));
                        }
                    }
                }
            }
        }
        // Direction priors: the node's six unknowns and those of the
        // shared world direction and bias, where solved.
        const Vec3 w = toVec3(m_frame.world);
        const Vec3 b = toVec3(m_frame.bias);
        const Mat32 Ew = tangentBasis(w);
        for (const DirectionPrior* prior : active_priors)
        {
            const DirectionPrior& p = *prior;
            const auto& x = m_nodes[p.node];
            const Vec3 r = priorResidual(x, p, w, b);
            std::vector<std::pair<Eigen::Index, Eigen::MatrixXd>> blocks;
            if (!fixed(p.node))
            {
                Eigen::MatrixXd J(3, 6);
                for (int k = 0; k < 6; ++k)
                {
                    Vec6 d = Vec6::Zero();
                    d[k] = h;
                    J.col(k) = (priorResidual(moved(x, d), p, w, b) -
                                priorResidual(moved(x, -d), p, w, b)) /
                               (2 * h);
                }
                blocks.emplace_back(col(p.node), J);
            }
            if (m_frame.solve_world)
            {
                Eigen::MatrixXd J(3, 2);
                for (int k = 0; k < 2; ++k)
                {
                    J.col(k) = (priorResidual(x, p, (w + h * Ew.col(k)).normalized(), b) -
                                priorResidual(x, p, (w - h * Ew.col(k)).normalized(), b)) /
                               (2 * h);
                }
                blocks.emplace_back(world_col, J);
            }
            if (m_frame.solve_bias)
            {
                Eigen::MatrixXd J(3, 2);
                for (int k = 0; k < 2; ++k)
                {
                    J.col(k) = (priorResidual(x, p, w, b + h * Eb.col(k)) -
                                priorResidual(x, p, w, b - h * Eb.col(k))) /
                               (2 * h);
                }
                blocks.emplace_back(bias_col, J);
            }
            const Mat3 W = p.information.asEigen();
            for (const auto& [ci, Ji] : blocks)
            {
                g.segment(ci, Ji.cols()) += Ji.transpose() * W * r;
                for (const auto& [cj, Jj] : blocks)
                {
                    const Eigen::MatrixXd Hij = Ji.transpose() * W * Jj;
                    for (Eigen::Index a = 0; a < Hij.rows(); ++a)
                    {
                        for (Eigen::Index c = 0; c < Hij.cols(); ++c)
                        {
                            triplets.emplace_back(ci + a, cj + c, Hij(a, c));
                        }
                    }
                }
            }
        }
        Eigen::SparseMatrix<double> H(dim, dim);
        H.setFromTriplets(triplets.begin(), triplets.end());
        const Eigen::VectorXd diag = H.diagonal();
        bool improved = false;
        for (int tries = 0; tries < 10 && !improved; ++tries)
        {
            Eigen::SparseMatrix<double> A = H;
            for (Eigen::Index k = 0; k < dim; ++k)
            {
                // A node no edge reaches keeps a regular system.
                A.coeffRef(k, k) += lambda * std::max(diag[k], 1e-9) + 1e-12;
            }
            if (!analysed)
            {
                // The pattern is the graph's: its ordering is found once.
                solver.analyzePattern(A);
                analysed = true;
            }
            solver.factorize(A);
            if (solver.info() != Eigen::Success)
            {
                lambda *= 10;
                continue;
            }
            const Eigen::VectorXd step = solver.solve(-g);
            std::vector<mrpt::poses::CPose3D> before = m_nodes;
            const DirectionFrame frame_before = m_frame;
            for (std::size_t i = first_free; i < n; ++i)
            {
                m_nodes[i] = moved(m_nodes[i], step.segment<6>(col(i)));
            }
            if (any_prior && m_frame.solve_world)
            {
                const Vec3 w_new = (w + Ew * step.segment<2>(world_col)).normalized();
                m_frame.world = {w_new.x(), w_new.y(), w_new.z()};
            }
            if (any_prior && m_frame.solve_bias)
            {
                Vec3 b_new = b + Eb * step.segment<2>(bias_col);
                if (m_frame.max_bias > 0 && b_new.norm() > m_frame.max_bias)
                {
                    b_new *= m_frame.max_bias / b_new.norm();
                }
                m_frame.bias = {b_new.x(), b_new.y(), b_new.z()};
            }
            const double c = activeCost();
            if (std::isfinite(c) && c <= res.final_cost)
            {
                improved = true;
                const double decrease = (res.final_cost - c) / std::max(res.final_cost, 1e-300);
                res.final_cost = c;
                lambda = std::max(lambda / 10, 1e-9);
                res.iterations = it + 1;
                if (decrease < min_relative_decrease)
                {
                    return res;
                }
            }
            else
            {
                m_nodes = std::move(before);
                m_frame = frame_before;
                lambda *= 10;
            }
        }
        if (!improved)
        {
            break;
        }
    }
    return res;
}

}  // namespace emslam::rectify
