// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/EnergyAtPoses.h>
#include <emslam/rectify/Revisit.h>
#include <emslam/rectify/TrajectoryRectifier.h>

#include <mrpt/core/bits_math.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

namespace emslam::rectify
{
namespace
{
/** A Gaussian draw with covariance scale² · c over the components of `dof`
 * (3: δx, δz, δθy). A covariance that is not positive definite falls back
 * to its diagonal. */
template <class Rng>
ActionDelta gaussianDelta(const ActionCovariance& c, int dof, double scale, Rng& rng)
{
    const int idx3[3] = {0, 2, 4};
    const int n = dof == 3 ? 3 : 6;
    Eigen::MatrixXd m(n, n);
    for (int r = 0; r < n; ++r)
    {
        for (int k = 0; k < n; ++k)
        {
            m(r, k) = c(dof == 3 ? idx3[r] : r, dof == 3 ? idx3[k] : k);
        }
    }
    Eigen::MatrixXd L;
    const Eigen::LLT<Eigen::MatrixXd> llt(m);
    if (llt.info() == Eigen::Success)
    {
        L = llt.matrixL();
    }
    else
    {
        L = m.diagonal().cwiseMax(0.0).cwiseSqrt().asDiagonal();
    }
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::VectorXd u(n);
    for (int k = 0; k < n; ++k)
    {
        u[k] = normal(rng);
    }
    const Eigen::VectorXd d = scale * (L * u);
    ActionDelta delta{};
    for (int k = 0; k < n; ++k)
    {
        delta[static_cast<std::size_t>(dof == 3 ? idx3[k] : k)] = d[k];
    }
    return delta;
}
/** pose_i = a_0 ⊕ … ⊕ a_i. */
std::vector<mrpt::poses::CPose3D> composedPoses(const std::vector<mrpt::poses::CPose3D>& actions)
{
    std::vector<mrpt::poses::CPose3D> poses;
    poses.reserve(actions.size());
    for (const auto& a : actions)
    {
        poses.push_back(poses.empty() ? a : poses.back() + a);
    }
    return poses;
}
}  // namespace

std::vector<double> TrajectoryRectifier::downstreamReach(const Trajectory& t)
{
    const auto& map = t.map();
    const std::size_t n = t.size();
    std::vector<double> farthest(n, 0.0);
    for (std::size_t j = 0; j < n; ++j)
    {
        double farthest_sq = 0.0;
        for (const auto& p : map.observationCloud(j).points)
        {
            farthest_sq =
                std::max(farthest_sq, double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
        }
        farthest[j] = std::sqrt(farthest_sq);
    }
    std::vector<double> reach(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
    {
        const auto origin = map.observationPose(i).translation();
        for (std::size_t j = i; j < n; ++j)
        {
            const double to_origin = (map.observationPose(j).translation() - origin).norm();
            reach[i] = std::max(reach[i], to_origin + farthest[j]);
        }
    }
    return reach;
}

double TrajectoryRectifier::largestMove() const
{
    double largest = 0.0;
    for (const Perturbation& p : m_change)
    {
        const auto& d = p.delta;
        const double shift = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const double turn = std::sqrt(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
        largest =
            std::max(largest, shift + turn * (p.index < m_reach.size() ? m_reach[p.index] : 0.0));
    }
    return largest;
}

TrajectoryRectifier::TrajectoryRectifier(const TRectifierOptions& p) : m_p(p), m_rng(p.seed)
{
    m_p.validate();
}

void TrajectoryRectifier::begin(Trajectory& t, RectificationStats& s)
{
    s = RectificationStats{};
    s.elements = t.size();
    s.frames = t.frameCount();
    t.setResolutionLevel(0);
    m_energy = t.empty() ? 0.0 : t.recomputeEnergy();
    s.energy_before = m_energy;
    s.energy_after = m_energy;
    m_best = t.actions();
    m_start = t.actions();
    // An O(points) pass: only a_0's capped turn and confirm_phases need it.
    const bool capped_turn = t.dependsOnGlobalAlignment() && m_p.proposal != ProposalShape::Box;
    m_reach.clear();
    if (capped_turn || m_p.confirm_phases >= 2)
    {
        m_reach = downstreamReach(t);
    }
    m_shifted_known = false;
    // An energy that anchors a_0 (Manhattan, flat floor) measures the
    // orientation against the world's structure from the first frame on:
    // that the egomotion never measured, so it is not held back.
    const bool blind = !t.empty() && !t.dependsOnGlobalAlignment();
    const bool asks_revisit =
        blind &&
        (m_p.hold_before_revisit || (m_p.confirm_phases >= 2 && m_p.confirm_all_before_revisit));
    const bool before_revisit = asks_revisit && !revisitsAPlace(t);
    m_confirm_all = m_p.confirm_phases >= 2 && m_p.confirm_all_before_revisit && before_revisit;
    m_hold = m_p.hold_before_revisit && before_revisit;
    s.held_before_revisit = m_hold;
    m_best_energy = m_energy;
    m_consecutive_failures = m_hold ? m_p.nc_max : 0;  // "stable": nothing to do yet
    m_reuse = false;
    if (m_p.coarse_levels > 0 && t.size() >= 2 && !m_hold)
    {
        startLevel(t, m_p.coarse_levels);
    }
}

void TrajectoryRectifier::restoreBestState(Trajectory& t)
{
    // Only the paper's rule keeps worse states; greedy is always at its best.
    if (m_p.acceptance != Acceptance::Greedy && m_energy > m_best_energy &&
        m_best.size() == t.size())
    {
        m_energy = t.setActions(m_best);
        t.commitChange();
    }
}

void TrajectoryRectifier::startLevel(Trajectory& t, int level)
{
    restoreBestState(t);
    t.setResolutionLevel(level);
    m_energy = t.recomputeEnergy();
    m_best = t.actions();
    m_best_energy = m_energy;
    m_consecutive_failures = 0;
    m_reuse = false;
    m_shifted_known = false;  // another cell size, maybe another state
}

bool TrajectoryRectifier::refine(Trajectory& t)
{
    if (t.resolutionLevel() == 0 || m_hold)
    {
        return false;
    }
    startLevel(t, t.resolutionLevel() - 1);
    return true;
}

void TrajectoryRectifier::drawPerturbation(const Trajectory& t)
{
    const std::size_t n = t.size();
    const bool anchor_first = t.dependsOnGlobalAlignment();
    // Candidates: all actions, or all but a_0 when the energy ignores the
    // global alignment (then moving a_0 would only waste attempts).
    const std::size_t first_free = anchor_first ? 1 : (n > 1 ? 1 : 0);
    const std::size_t pool = n - first_free;
    std::size_t count = static_cast<std::size_t>(
        std::max<long>(1, std::lround(m_p.select_fraction * static_cast<double>(n))));

    m_indices.clear();
    m_coherent = m_p.proposal == ProposalShape::Coherent && !m_coherent && pool > 0;
    if (m_coherent)
    {
        // A run of consecutive actions, one shared draw (below).
        const std::size_t run = std::min(std::max<std::size_t>(1, count), pool);
        std::uniform_int_distribution<std::size_t> start(first_free, n - run);
        const std::size_t k0 = start(m_rng);
        for (std::size_t k = 0; k < run; ++k)
        {
            m_indices.push_back(k0 + k);
        }
        count = 0;
    }
    else if (anchor_first)
    {
        // a_0 comes on top of at least one other action: with S_sel = 1
        // alone the trajectory itself would never bend.
        m_indices.push_back(0);
        count = std::max<std::size_t>(count, 2) - 1;  // count <= n: select_fraction <= 1
    }
    count = std::min(count, pool);
    // Partial Fisher-Yates over [first_free, n).
    std::vector<std::size_t>& candidates = m_candidates;
    candidates.resize(pool);
    std::iota(candidates.begin(), candidates.end(), first_free);
    for (std::size_t k = 0; k < count; ++k)
    {
        std::uniform_int_distribution<std::size_t> pick(k, pool - 1);
        std::swap(candidates[k], candidates[pick(m_rng)]);
        m_indices.push_back(candidates[k]);
    }

    const double eps_t = m_p.eps_xyz;
    const double eps_r = mrpt::DEG2RAD(m_p.eps_rot_deg);
    // a_0 turns the whole map about the first camera. Beside the paper
    // (with the egomotion's proposals) its turn is kept to what moves no
    // point by more than a cell: a larger one changes a Manhattan energy
    // more than the bends of the other actions can, and almost every
    // attempt fails (doc/rectify.md, "The global alignment's turn").
    const double eps_r0 = m_p.proposal != ProposalShape::Box && t.dependsOnGlobalAlignment() &&
                                  !m_reach.empty() && m_reach[0] > 0
                              ? std::min(eps_r, t.map().creationOptions().cell_size / m_reach[0])
                              : eps_r;
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const bool planar = t.dof() == 3;
    m_change.clear();
    const bool from_covariance = m_p.proposal != ProposalShape::Box;
    for (std::size_t index : m_indices)
    {
        Perturbation p;
        p.index = index;
        const double eps_rot = index == 0 ? eps_r0 : eps_r;
        if (m_coherent && !m_change.empty())
        {
            p.delta = m_change.front().delta;
        }
        else if (from_covariance && index > 0)
        {
            p.delta =
                gaussianDelta(t.referenceCovariance(index), t.dof(), m_p.proposal_scale, m_rng);
        }
        else if (planar)
        {
            p.delta = {eps_t * unit(m_rng),   0.0, eps_t * unit(m_rng), 0.0,
                       eps_rot * unit(m_rng), 0.0};
        }
        else
        {
            for (int c = 0; c < 3; ++c)
                p.delta[c] = eps_t * unit(m_rng);
            for (int c = 3; c < 6; ++c)
                p.delta[c] = eps_rot * unit(m_rng);
        }
        m_change.push_back(p);
    }
}

bool TrajectoryRectifier::attempt(Trajectory& t, RectificationStats& s)
{
    if (t.size() < 2 || m_hold)
    {
        return false;
    }
    const auto t0 = std::chrono::steady_clock::now();
    if (!(m_p.reuse_success && m_reuse))
    {
        drawPerturbation(t);
    }
    m_changes.clear();
    for (const Perturbation& p : m_change)
    {
        m_changes.push_back({p.index, perturbAction(t.action(p.index), p.delta)});
    }
    // A move beyond a cell can land on a look-alike place that only this
    // grid's binning favours (doc/rectify.md, "Confirming long moves"); a
    // smaller one can win by the grid's noise alone ("Confirming every
    // success").
    const bool check = m_p.confirm_phases >= 2 &&
                       (m_confirm_all || m_p.confirm_min_move == 0 ||
                        largestMove() > m_p.confirm_min_move * t.map().creationOptions().cell_size);
    const double entropy_before = check ? t.entropy() : 0.0;
    if (check)
    {
        m_before = t.actions();
    }
    const double e_try = t.changeActions(m_changes);
    ++s.attempts;
    if (t.resolutionLevel() > 0)
    {
        ++s.coarse_attempts;
    }

    bool success = e_try < m_energy - m_p.min_improvement * std::abs(m_energy);
    bool unconfirmed = false;
    if (success && check)
    {
        if (!m_shifted_known)
        {
            m_shifted_energy = confirmationEnergy(t, m_before, entropy_before);
        }
        const double shifted_try = confirmationEnergy(t, t.actions(), t.entropy());
        m_shifted_known = true;
        unconfirmed = !(shifted_try < m_shifted_energy);
        success = !unconfirmed;
        if (success)
        {
            m_shifted_energy = shifted_try;
        }
    }
    else if (success)
    {
        m_shifted_known = false;  // the state moved unchecked
    }
    if (success)
    {
        ++s.successes;
        m_consecutive_failures = 0;
        m_energy = e_try;
        t.commitChange();
        m_reuse = true;
        if (e_try < m_best_energy)
        {
            m_best_energy = e_try;
            if (m_p.acceptance != Acceptance::Greedy)
            {
                m_best = t.actions();
            }
        }
    }
    else
    {
        ++s.failures;
        s.unconfirmed += unconfirmed ? 1 : 0;
        ++m_consecutive_failures;
        m_reuse = false;
        bool keep = false;
        if (m_p.acceptance == Acceptance::Ratio && !unconfirmed && e_try > 0 &&
            std::isfinite(e_try))
        {
            std::uniform_real_distribution<double> u(0.0, 1.0);
            keep = u(m_rng) < m_energy / e_try;
        }
        if (keep)
        {
            ++s.accepted_worse;
            m_energy = e_try;
            t.commitChange();
            m_shifted_known = false;
        }
        else
        {
            m_energy = t.revertLastChange();
        }
    }
    s.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    s.energy_after = m_best_energy;
    s.energy_trace.push_back(static_cast<float>(m_energy));
    return success;
}

void TrajectoryRectifier::finish(Trajectory& t, RectificationStats& s)
{
    if (t.resolutionLevel() > 0)
    {
        startLevel(t, 0);  // stopped or capped on a coarse level
    }
    restoreBestState(t);
    if (m_p.validate_phases >= 2 && m_start.size() == t.size() && t.actions() != m_start &&
        !shiftedGridsConfirm(t))
    {
        m_energy = t.setActions(m_start);
        t.commitChange();
        s.rejected_by_validation = true;
    }
    s.energy_after = t.empty() ? 0.0 : m_energy;
    s.converged = m_consecutive_failures >= m_p.nc_max;
}

double TrajectoryRectifier::shiftedGridsEnergy(
    const Trajectory& t, const std::vector<mrpt::poses::CPose3D>& actions, int phases)
{
    return entropyAtElementPoses(t, composedPoses(actions), phases) + t.priorEnergyOf(actions);
}

double TrajectoryRectifier::confirmationEnergy(
    const Trajectory& t,
    const std::vector<mrpt::poses::CPose3D>& actions,
    double grid_entropy) const
{
    const int phases = m_p.confirm_phases;
    if (t.gridPhases() != 1)
    {
        return shiftedGridsEnergy(t, actions, phases);
    }
    // Grid 0 is the trajectory's own: its entropy is known.
    const std::vector<mrpt::poses::CPose3D> poses = composedPoses(actions);
    double sum = grid_entropy;
    for (int k = 1; k < phases; ++k)
    {
        sum += entropyOnShiftedGrid(t, poses, k, phases);
    }
    return sum / phases + t.priorEnergyOf(actions);
}

bool TrajectoryRectifier::shiftedGridsConfirm(const Trajectory& t) const
{
    return shiftedGridsEnergy(t, t.actions(), m_p.validate_phases) <
           shiftedGridsEnergy(t, m_start, m_p.validate_phases);
}

RectificationStats TrajectoryRectifier::rectify(Trajectory& t, const std::atomic<bool>* stop)
{
    RectificationStats s;
    begin(t, s);
    const auto t0 = std::chrono::steady_clock::now();
    do
    {
        while (t.size() >= 2 && m_consecutive_failures < m_p.nc_max &&
               (m_p.max_attempts == 0 || s.attempts < static_cast<std::size_t>(m_p.max_attempts)) &&
               !(stop && stop->load(std::memory_order_relaxed)))
        {
            attempt(t, s);
        }
    } while (m_consecutive_failures >= m_p.nc_max && refine(t));
    finish(t, s);
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return s;
}

}  // namespace emslam::rectify
