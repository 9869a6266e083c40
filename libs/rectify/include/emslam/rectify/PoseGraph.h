// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/ActionCovariance.h>

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <functional>
#include <vector>

namespace emslam::rectify
{
/** A graph of camera poses tied by measured relative poses, solved by
 * Levenberg–Marquardt on the sum of squared Mahalanobis residuals:
 *
 *   E = ½ Σ_edges δ_eᵀ Ω_e δ_e,   δ_e = actionDifference(x_i⁻¹ ⊕ x_j, z_e),
 *
 * with x the node poses (world), z_e the measured pose of node j in node i
 * and Ω_e its information (inverse covariance, in the convention of
 * ActionCovariance). Direction priors add ½ ρᵀ Λ ρ,
 * ρ = normalize(u − b) − R_iᵀ w: a direction `u` measured in node i (e.g. the
 * up a camera sees), less the sensor's own bias `b` (node frame, the same
 * for every node), should be the world direction `w`. w and b may be
 * unknowns solved with the nodes (two degrees of freedom each). Node 0 is held fixed (the world is
 * the first camera). Each node moves by x ← perturbAction(x, δ), so every node has six unknowns;
 * the normal equations are sparse (a chain plus the loop edges) and solved
 * with a sparse Cholesky factorization.
 *
 * Why: a loop's closing edge says where the path ends relative to where it
 * began; spread over the chain by the chain's own covariances it bends every
 * pose, not just the trajectory elements the rectifier may move.
 * \ingroup emslam_rectify_grp \sa emslam::slam::LoopCloser */
class PoseGraph
{
public:
    /** A relative-pose measurement between two nodes. */
    struct Edge
    {
        /** The nodes it joins. */
        ///@{
        std::size_t from{0}, to{0};
        ///@}
        mrpt::poses::CPose3D measurement;  //!< pose of node `to` in node `from`
        ActionCovariance information;      //!< inverse covariance of `measurement`
        std::size_t tag{0};                //!< the caller's: what kind of edge, which one
    };
    /** A direction measured in a node that should be the world direction. */
    struct DirectionPrior
    {
        std::size_t node{0};                      //!< the node the direction was measured in
        mrpt::math::TVector3D in_node;            //!< measured, unit, node frame
        mrpt::math::CMatrixDouble33 information;  //!< of `in_node`, node frame
    };
    /** What the direction priors share. */
    struct DirectionFrame
    {
        mrpt::math::TVector3D world{0, -1, 0};  //!< w, unit
        mrpt::math::TVector3D bias{0, 0, 0};    //!< b, node frame
        bool solve_world{false};                //!< w is an unknown
        /** b is an unknown, orthogonal to the mean measured direction (a
         * tilt of what the sensor sees, not a length). */
        bool solve_bias{false};
        /** [rad] when > 0, a solved b stays within this tilt: each step is
         * pulled back onto the bound. Without it a bias the measurements
         * cannot tell from the world up runs off to where normalize(u − b)
         * no longer depends on u (every residual zero, b meaningless). */
        double max_bias{0};
    };
    /** What optimize() did. */
    struct Result
    {
        int iterations{0};       //!< Levenberg–Marquardt iterations run
        double initial_cost{0};  //!< E before
        double final_cost{0};    //!< E after
        bool stopped{false};     //!< cut short by `stop`
    };

    /** Appends a node at world pose `pose`; returns its index. */
    std::size_t addNode(const mrpt::poses::CPose3D& pose);
    /** Adds an edge between existing nodes `from` != `to` with this
     * covariance (its inverse is taken, see informationOf()). Throws
     * std::out_of_range / std::invalid_argument otherwise. */
    void addEdge(
        std::size_t from,
        std::size_t to,
        const mrpt::poses::CPose3D& measurement,
        const ActionCovariance& covariance,
        std::size_t tag = 0);
    /** Adds `e` as it is (its information, its tag): e.g. an edge of a saved
     * graph. Throws as the other addEdge(). */
    void addEdge(const Edge& e);
    /** Removes every edge for which `drop` is true; returns how many. */
    std::size_t removeEdgesIf(const std::function<bool(const Edge&)>& drop);
    /** Replaces the measurement of edge `index` (std::out_of_range otherwise). */
    void setEdgeMeasurement(std::size_t index, const mrpt::poses::CPose3D& measurement);
    /** Moves node `index` (std::out_of_range otherwise). */
    void setNode(std::size_t index, const mrpt::poses::CPose3D& pose);
    /** Adds a direction prior on an existing node (std::out_of_range
     * otherwise); `information` may be singular (a direction has two
     * degrees of freedom). */
    void addDirectionPrior(
        std::size_t node,
        const mrpt::math::TVector3D& in_node,
        const mrpt::math::CMatrixDouble33& information);
    /** Sets the world up and bias, and which of them optimize() solves. */
    void setDirectionFrame(const DirectionFrame& f) { m_frame = f; }
    /** After optimize(): with the solved w and b. */
    const DirectionFrame& directionFrame() const { return m_frame; }
    /** Removes every direction prior. */
    void clearDirectionPriors() { m_priors.clear(); }
    /** The direction priors, in the order added. */
    const std::vector<DirectionPrior>& directionPriors() const { return m_priors; }
    /** ½ ρᵀ Λ ρ of one prior at the current nodes. */
    double priorCost(const DirectionPrior& p) const;
    /** Number of nodes. */
    std::size_t nodeCount() const { return m_nodes.size(); }
    /** The edges, in the order added (removeEdgesIf() keeps the order). */
    const std::vector<Edge>& edges() const { return m_edges; }
    /** World pose of node `i` (std::out_of_range otherwise). */
    const mrpt::poses::CPose3D& node(std::size_t i) const { return m_nodes.at(i); }
    /** World poses of every node. */
    const std::vector<mrpt::poses::CPose3D>& nodes() const { return m_nodes; }

    /** E at the current nodes. */
    double cost() const;
    /** ½ δᵀ Ω δ of one edge at the current nodes. */
    double edgeCost(const Edge& e) const;
    /** Levenberg–Marquardt until the relative decrease of E falls below
     * `min_relative_decrease`, or the decrease the next step is predicted
     * to bring (from the last factorisation) below `min_decrease`, or
     * `max_iterations`, or `stop` returning true before an iteration after
     * the first (the nodes stay where the last iteration left them); node 0 and every node
     * before `first_free` stay where they are (a local solve: only the
     * edges that reach a free node are looked at, so its cost follows them,
     * not the graph). Every direction prior counts: a free node's moves its
     * node, and each pulls on w and b where they are solved (so with every
     * node fixed, `first_free` >= nodeCount(), only w and b move). Result
     * costs are of those edges and of the priors that count. */
    Result optimize(
        int max_iterations = 30,
        std::size_t first_free = 1,
        double min_relative_decrease = 1e-9,
        double min_decrease = 0,
        const std::function<bool()>& stop = {});

    /** Nodes before `count` never move in optimize(), whatever its
     * `first_free` (e.g. a saved map a new run is localized in). */
    void setFixedPrefix(std::size_t count) { m_fixed_prefix = count; }
    /** See setFixedPrefix() (1: node 0 only, the world). */
    std::size_t fixedPrefix() const { return m_fixed_prefix; }

private:
    std::vector<mrpt::poses::CPose3D> m_nodes;
    std::size_t m_fixed_prefix{1};
    std::vector<Edge> m_edges;
    std::vector<DirectionPrior> m_priors;
    DirectionFrame m_frame;
};

}  // namespace emslam::rectify
