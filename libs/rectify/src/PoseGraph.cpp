// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/rectify/PoseGraph.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
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
    const ActionCovariance& covariance)
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
    m_edges.push_back({from, to, measurement, informationOf(covariance, 6)});
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
    return c;
}

PoseGraph::Result PoseGraph::optimize(int max_iterations)
{
    Result res;
    res.initial_cost = cost();
    res.final_cost = res.initial_cost;
    const std::size_t n = m_nodes.size();
    if (n < 2 || m_edges.empty())
    {
        return res;
    }
    // Node 0 is fixed: unknowns are nodes 1..n-1, six each.
    const auto dim = static_cast<Eigen::Index>(6 * (n - 1));
    const auto col = [](std::size_t node) { return static_cast<Eigen::Index>(6 * (node - 1)); };
    double lambda = 1e-4;
    constexpr double h = 1e-6;  // central differences of a smooth residual
    for (int it = 0; it < max_iterations; ++it)
    {
        std::vector<Eigen::Triplet<double>> triplets;
        triplets.reserve(m_edges.size() * 144);
        Eigen::VectorXd g = Eigen::VectorXd::Zero(dim);
        for (const auto& e : m_edges)
        {
            const auto& xi = m_nodes[e.from];
            const auto& xj = m_nodes[e.to];
            const Vec6 r = residual(xi, xj, e.measurement);
            Mat6x12 J;
            for (int k = 0; k < 6; ++k)
            {
                Vec6 d = Vec6::Zero();
                d[k] = h;
                J.col(k) = (residual(moved(xi, d), xj, e.measurement) -
                            residual(moved(xi, -d), xj, e.measurement)) /
                           (2 * h);
                J.col(6 + k) = (residual(xi, moved(xj, d), e.measurement) -
                                residual(xi, moved(xj, -d), e.measurement)) /
                               (2 * h);
            }
            const Mat6 W = toMat(e.information);
            const Eigen::Matrix<double, 12, 12> H = J.transpose() * W * J;
            const Eigen::Matrix<double, 12, 1> b = J.transpose() * W * r;
            const std::size_t ends[2] = {e.from, e.to};
            for (int a = 0; a < 2; ++a)
            {
                if (ends[a] == 0)
                {
                    continue;
                }
                g.segment<6>(col(ends[a])) += b.segment<6>(6 * a);
                for (int c = 0; c < 2; ++c)
                {
                    if (ends[c] == 0)
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
            Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
            if (solver.info() != Eigen::Success)
            {
                lambda *= 10;
                continue;
            }
            const Eigen::VectorXd step = solver.solve(-g);
            std::vector<mrpt::poses::CPose3D> before = m_nodes;
            for (std::size_t i = 1; i < n; ++i)
            {
                m_nodes[i] = moved(m_nodes[i], step.segment<6>(col(i)));
            }
            const double c = cost();
            if (std::isfinite(c) && c <= res.final_cost)
            {
                improved = true;
                const double decrease = (res.final_cost - c) / std::max(res.final_cost, 1e-300);
                res.final_cost = c;
                lambda = std::max(lambda / 10, 1e-9);
                res.iterations = it + 1;
                if (decrease < 1e-9)
                {
                    return res;
                }
            }
            else
            {
                m_nodes = std::move(before);
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
