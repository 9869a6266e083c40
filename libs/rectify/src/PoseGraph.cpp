// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/rectify/PoseGraph.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <functional>
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

using Triplets = std::vector<Eigen::Triplet<double>>;
using Solver = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>;

/** Where the unknowns sit in the normal equations: six per free node, then
 * the shared world direction and bias of the direction priors (two each). */
struct Unknowns
{
    std::size_t first_free{1};
    bool solve_world{false}, solve_bias{false};
    Eigen::Index world_col{0}, bias_col{0}, dim{0};
    Mat32 Eb;  //!< the bias moves orthogonally to the mean measured direction

    Eigen::Index col(std::size_t node) const
    {
        return static_cast<Eigen::Index>(6 * (node - first_free));
    }
    bool fixed(std::size_t node) const { return node < first_free; }
};

Unknowns unknownsOf(
    std::size_t n,
    std::size_t first_free,
    const std::vector<PoseGraph::DirectionPrior>& priors,
    const PoseGraph::DirectionFrame& frame)
{
    Unknowns u;
    u.first_free = first_free;
    const bool any_prior = !priors.empty();
    u.solve_world = any_prior && frame.solve_world;
    u.solve_bias = any_prior && frame.solve_bias;
    u.world_col = static_cast<Eigen::Index>(6 * (n - first_free));
    u.bias_col = u.world_col + (u.solve_world ? 2 : 0);
    u.dim = u.bias_col + (u.solve_bias ? 2 : 0);
    Vec3 mean_measured = Vec3::Zero();
    for (const auto& p : priors)
    {
        mean_measured += toVec3(p.in_node);
    }
    u.Eb = tangentBasis(mean_measured.norm() > 0 ? mean_measured.normalized() : Vec3::UnitY());
    return u;
}

/** The linearization point of the shared direction unknowns. */
struct FramePoint
{
    Vec3 w, b;
    Mat32 Ew;  //!< moves of w: tangent to it
};

/** One edge's J ᵀW J (its lower triangle: the solver reads no other) and
 * J ᵀW r, on the free ends' unknowns. */
void addEdgeTerms(
    const PoseGraph::Edge& e,
    const std::vector<mrpt::poses::CPose3D>& nodes,
    const Unknowns& u,
    Triplets& triplets,
    Eigen::VectorXd& g)
{
    const auto& xi = nodes[e.from];
    const auto& xj = nodes[e.to];
    const Vec6 r = residual(xi, xj, e.measurement);
    const Mat6x12 J = edgeJacobian(xi, xj, r);
    const Mat6 W = toMat(e.information);
    const Eigen::Matrix<double, 12, 12> H = J.transpose() * W * J;
    const Eigen::Matrix<double, 12, 1> b = J.transpose() * W * r;
    const std::size_t ends[2] = {e.from, e.to};
    for (int a = 0; a < 2; ++a)
    {
        if (u.fixed(ends[a]))
        {
            continue;
        }
        g.segment<6>(u.col(ends[a])) += b.segment<6>(6 * a);
        for (int c = 0; c < 2; ++c)
        {
            if (u.fixed(ends[c]) || u.col(ends[a]) < u.col(ends[c]))
            {
                continue;
            }
            for (int p = 0; p < 6; ++p)
            {
                for (int q = 0; q < 6; ++q)
                {
                    triplets.emplace_back(
                        u.col(ends[a]) + p, u.col(ends[c]) + q, H(6 * a + p, 6 * c + q));
                }
            }
        }
    }
}

/** A direction prior's Jacobian blocks, by central differences of a smooth
 * residual: the node's six unknowns and those of the shared world direction
 * and bias, where solved; each with its first column. */
std::vector<std::pair<Eigen::Index, Eigen::MatrixXd>> priorJacobian(
    const PoseGraph::DirectionPrior& p,
    const mrpt::poses::CPose3D& x,
    const FramePoint& fp,
    const Unknowns& u)
{
    constexpr double h = 1e-6;
    const Vec3& w = fp.w;
    const Vec3& b = fp.b;
    std::vector<std::pair<Eigen::Index, Eigen::MatrixXd>> blocks;
    if (!u.fixed(p.node))
    {
        Eigen::MatrixXd J(3, 6);
        for (int k = 0; k < 6; ++k)
        {
            Vec6 d = Vec6::Zero();
            d[k] = h;
            J.col(k) =
                (priorResidual(moved(x, d), p, w, b) - priorResidual(moved(x, -d), p, w, b)) /
                (2 * h);
        }
        blocks.emplace_back(u.col(p.node), J);
    }
    if (u.solve_world)
    {
        Eigen::MatrixXd J(3, 2);
        for (int k = 0; k < 2; ++k)
        {
            J.col(k) = (priorResidual(x, p, (w + h * fp.Ew.col(k)).normalized(), b) -
                        priorResidual(x, p, (w - h * fp.Ew.col(k)).normalized(), b)) /
                       (2 * h);
        }
        blocks.emplace_back(u.world_col, J);
    }
    if (u.solve_bias)
    {
        Eigen::MatrixXd J(3, 2);
        for (int k = 0; k < 2; ++k)
        {
            J.col(k) = (priorResidual(x, p, w, b + h * u.Eb.col(k)) -
                        priorResidual(x, p, w, b - h * u.Eb.col(k))) /
                       (2 * h);
        }
        blocks.emplace_back(u.bias_col, J);
    }
    return blocks;
}

/** One direction prior's J ᵀΛ J (its lower triangle) and J ᵀΛ ρ. */
void addPriorTerms(
    const PoseGraph::DirectionPrior& p,
    const mrpt::poses::CPose3D& x,
    const FramePoint& fp,
    const Unknowns& u,
    Triplets& triplets,
    Eigen::VectorXd& g)
{
    const Vec3 r = priorResidual(x, p, fp.w, fp.b);
    const auto blocks = priorJacobian(p, x, fp, u);
    const Mat3 W = p.information.asEigen();
    for (const auto& [ci, Ji] : blocks)
    {
        g.segment(ci, Ji.cols()) += Ji.transpose() * W * r;
        for (const auto& [cj, Jj] : blocks)
        {
            if (ci < cj)
            {
                continue;
            }
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

/** Moves the free nodes, w and b (where solved) by `step`; a solved b is
 * pulled back onto its bound. */
void applyStep(
    const Eigen::VectorXd& step,
    const Unknowns& u,
    const FramePoint& fp,
    std::vector<mrpt::poses::CPose3D>& nodes,
    PoseGraph::DirectionFrame& frame)
{
    for (std::size_t i = u.first_free; i < nodes.size(); ++i)
    {
        nodes[i] = moved(nodes[i], step.segment<6>(u.col(i)));
    }
    if (u.solve_world)
    {
        const Vec3 w_new = (fp.w + fp.Ew * step.segment<2>(u.world_col)).normalized();
        frame.world = {w_new.x(), w_new.y(), w_new.z()};
    }
    if (u.solve_bias)
    {
        Vec3 b_new = fp.b + u.Eb * step.segment<2>(u.bias_col);
        if (frame.max_bias > 0 && b_new.norm() > frame.max_bias)
        {
            b_new *= frame.max_bias / b_new.norm();
        }
        frame.bias = {b_new.x(), b_new.y(), b_new.z()};
    }
}

/** H + λ diag(H), the Levenberg–Marquardt damping. */
Eigen::SparseMatrix<double> damped(
    const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& diag, double lambda)
{
    Eigen::SparseMatrix<double> A = H;
    for (Eigen::Index k = 0; k < A.rows(); ++k)
    {
        // A node no edge reaches keeps a regular system.
        A.coeffRef(k, k) += lambda * std::max(diag[k], 1e-9) + 1e-12;
    }
    return A;
}

/** The indices of the edges with an end at or after `first_free`. */
std::vector<std::size_t> edgesReaching(
    const std::vector<PoseGraph::Edge>& edges, std::size_t first_free)
{
    std::vector<std::size_t> active;
    for (std::size_t e = 0; e < edges.size(); ++e)
    {
        if (edges[e].from >= first_free || edges[e].to >= first_free)
        {
            active.push_back(e);
        }
    }
    return active;
}

/** Levenberg–Marquardt's λ and the factorization whose ordering is kept. */
struct Damping
{
    double lambda{1e-4};
    Solver solver;
    bool analysed{false};
};

enum class StepOutcome
{
    Rejected,   //!< no λ of ten tries lowered the cost: nodes and frame as before
    Improved,   //!< moved, the cost fell
    Converged,  //!< moved, the cost fell by less than the relative decrease asked
};

/** Solves (H + λ diag H) δ = −g and keeps the step if the cost does not
 * rise, else restores the nodes and frame and tries again with 10 λ (up to
 * ten tries); `final_cost` follows the kept steps. */
StepOutcome dampedStep(
    const Eigen::SparseMatrix<double>& H,
    const Eigen::VectorXd& g,
    const Unknowns& u,
    const FramePoint& fp,
    const std::function<double()>& cost,
    double min_relative_decrease,
    Damping& damping,
    std::vector<mrpt::poses::CPose3D>& nodes,
    PoseGraph::DirectionFrame& frame,
    double& final_cost)
{
    const Eigen::VectorXd diag = H.diagonal();
    for (int tries = 0; tries < 10; ++tries)
    {
        const Eigen::SparseMatrix<double> A = damped(H, diag, damping.lambda);
        if (!damping.analysed)
        {
            // The pattern is the graph's: its ordering is found once.
            damping.solver.analyzePattern(A);
            damping.analysed = true;
        }
        damping.solver.factorize(A);
        if (damping.solver.info() != Eigen::Success)
        {
            damping.lambda *= 10;
            continue;
        }
        std::vector<mrpt::poses::CPose3D> before = nodes;
        const PoseGraph::DirectionFrame frame_before = frame;
        applyStep(damping.solver.solve(-g), u, fp, nodes, frame);
        const double c = cost();
        if (std::isfinite(c) && c <= final_cost)
        {
            const double decrease = (final_cost - c) / std::max(final_cost, 1e-300);
            final_cost = c;
            damping.lambda = std::max(damping.lambda / 10, 1e-9);
            return decrease < min_relative_decrease ? StepOutcome::Converged
                                                    : StepOutcome::Improved;
        }
        nodes = std::move(before);
        frame = frame_before;
        damping.lambda *= 10;
    }
    return StepOutcome::Rejected;
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
    addEdge(Edge{from, to, measurement, informationOf(covariance, 6), tag});
}

void PoseGraph::addEdge(const Edge& e)
{
    if (e.from >= m_nodes.size() || e.to >= m_nodes.size())
    {
        throw std::out_of_range(
            "PoseGraph::addEdge: node " + std::to_string(std::max(e.from, e.to)) + " of " +
            std::to_string(m_nodes.size()));
    }
    if (e.from == e.to)
    {
        throw std::invalid_argument("PoseGraph::addEdge: an edge needs two different nodes");
    }
    m_edges.push_back(e);
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
    int max_iterations,
    std::size_t first_free,
    double min_relative_decrease,
    double min_decrease,
    const std::function<bool()>& stop)
{
    const std::size_t n = m_nodes.size();
    first_free = std::min(std::max<std::size_t>({first_free, 1, m_fixed_prefix}), n);
    // Only the edges that reach a free node change the cost.
    const std::vector<std::size_t> active = edgesReaching(m_edges, first_free);
    // Nodes before first_free are fixed (node 0 always: the world). The
    // priors of fixed nodes pull on the shared world direction and bias
    // only: without them, they change nothing.
    const Unknowns u = unknownsOf(n, first_free, m_priors, m_frame);
    std::vector<const DirectionPrior*> active_priors;
    for (const auto& p : m_priors)
    {
        if (u.solve_world || u.solve_bias || p.node >= first_free)
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
    Damping damping;
    for (int it = 0; it < max_iterations; ++it)
    {
        if (it > 0 && stop && stop())
        {
            res.stopped = true;
            return res;
        }
        Triplets triplets;
        triplets.reserve(active.size() * 108);
        Eigen::VectorXd g = Eigen::VectorXd::Zero(u.dim);
        for (std::size_t ei : active)
        {
            addEdgeTerms(m_edges[ei], m_nodes, u, triplets, g);
        }
        const Vec3 w = toVec3(m_frame.world);
        const FramePoint fp{w, toVec3(m_frame.bias), tangentBasis(w)};
        for (const DirectionPrior* p : active_priors)
        {
            addPriorTerms(*p, m_nodes[p->node], fp, u, triplets, g);
        }
        Eigen::SparseMatrix<double> H(u.dim, u.dim);
        H.setFromTriplets(triplets.begin(), triplets.end());
        // The last factorisation predicts the decrease of the step from
        // here, ½ gᵀA⁻¹g, without the new one (most of an iteration's time).
        if (it > 0 && min_decrease > 0 && 0.5 * g.dot(damping.solver.solve(g)) < min_decrease)
        {
            return res;
        }
        const StepOutcome outcome = dampedStep(
            H, g, u, fp, activeCost, min_relative_decrease, damping, m_nodes, m_frame,
            res.final_cost);
        if (outcome == StepOutcome::Rejected)
        {
            break;
        }
        res.iterations = it + 1;
        if (outcome == StepOutcome::Converged)
        {
            return res;
        }
    }
    return res;
}

}  // namespace emslam::rectify
