// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/rectify/Trajectory.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace emslam::rectify
{
using emslam::maps::EnergyType;

Trajectory::Trajectory(
    const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
    const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options)
    : m_map(map_options, insertion_options), m_base_cell_size(m_map.creationOptions().cell_size)
{
}

bool Trajectory::dependsOnGlobalAlignment() const
{
    const EnergyType e = m_map.creationOptions().energy;
    return e == EnergyType::LowStructured || e == EnergyType::Structured ||
           e == EnergyType::PlanarStructured;
}

void Trajectory::append(
    const mrpt::poses::CPose3D& action,
    const emslam::maps::WeightedPointCloud& cloud,
    double timestamp,
    std::size_t frame_index,
    const std::optional<ActionCovariance>& covariance)
{
    setResolutionLevel(0);  // the new cloud is simplified at l_d
    // The caller's action starts at the last frame, which after compression
    // is not the last element's origin.
    mrpt::poses::CPose3D a = action;
    ActionCovariance cov = covariance ? *covariance : m_prior.stepCovariance();
    if (!m_frames.empty())
    {
        const mrpt::poses::CPose3D& inside = m_frames.back().back().T_element_frame;
        a = inside + action;
        cov = transportCovariance(inside, cov);
    }
    if (dof() == 3)
    {
        a = planarAction(a);
    }
    const mrpt::poses::CPose3D pose = m_actions.empty() ? a : this->pose(m_actions.size() - 1) + a;
    const std::size_t index = m_map.insertWeightedCloud(cloud, pose);
    double farthest_sq = m_view_range * m_view_range;  // one square root per frame
    for (const auto& q : m_map.observationCloud(index).points)
    {
        farthest_sq =
            std::max(farthest_sq, double(q.x) * q.x + double(q.y) * q.y + double(q.z) * q.z);
    }
    m_view_range = std::sqrt(farthest_sq);
    for (auto& ph : m_phase_maps)
    {
        ph.map.insertWeightedCloud(m_map.observationCloud(index), ph.shift + pose, true);
    }
    m_actions.push_back(a);
    m_reference.push_back(a);
    m_reference_cov.push_back(cov);
    m_reference_info.push_back(informationOf(cov, dof()));
    m_frames.push_back({ElementFrame{timestamp, frame_index, mrpt::poses::CPose3D()}});
    m_prior_terms.push_back(0.0);  // the action equals its reference
    m_undo_valid = false;
}

double Trajectory::entropy() const
{
    return phaseMean(m_map.energy());
}

double Trajectory::phaseMean(double e0) const
{
    if (m_phase_maps.empty())
    {
        return e0;
    }
    double sum = e0;
    for (const auto& ph : m_phase_maps)
    {
        sum += ph.map.energy();
    }
    return sum / static_cast<double>(m_phase_maps.size() + 1);
}

void Trajectory::setGridPhases(int phases)
{
    if (phases < 1 || phases > 8)
    {
        throw std::invalid_argument(
            "Trajectory::setGridPhases: " + std::to_string(phases) + " is not in 1..8");
    }
    const double cell = m_map.creationOptions().cell_size;
    m_phase_maps.clear();
    for (int k = 1; k < phases; ++k)
    {
        m_phase_maps.push_back(
            {gridPhaseShift(k, phases, cell),
             emslam::CEntropyVoxelMap(m_map.creationOptions(), m_map.insertionOptions)});
    }
    rebuildPhaseMaps();
}

void Trajectory::setThreads(int threads)
{
    m_map.setThreads(threads);
    for (auto& ph : m_phase_maps)
    {
        ph.map.setThreads(threads);
    }
}

void Trajectory::setResolutionLevel(int level)
{
    if (level < 0 || level > 4)
    {
        throw std::invalid_argument(
            "Trajectory::setResolutionLevel: " + std::to_string(level) + " is not in 0..4");
    }
    if (level == m_level)
    {
        return;
    }
    m_level = level;
    auto options = m_map.creationOptions();
    options.cell_size = std::ldexp(m_base_cell_size, level);
    m_undo_valid = false;
    m_map.setCreationOptions(options);  // re-bins every observation
    setGridPhases(gridPhases());        // the shifts are fractions of the new cell
}

mrpt::poses::CPose3D Trajectory::gridPhaseShift(int k, int phases, double cell_size)
{
    const double d = cell_size * k / phases;
    return mrpt::poses::CPose3D(d, d, d, 0, 0, 0);
}

void Trajectory::rebuildPhaseMaps()
{
    for (auto& ph : m_phase_maps)
    {
        ph.map = emslam::CEntropyVoxelMap(m_map.creationOptions(), m_map.insertionOptions);
        ph.map.setThreads(m_map.threads());
        for (std::size_t i = 0; i < m_map.observationCount(); ++i)
        {
            ph.map.insertWeightedCloud(
                m_map.observationCloud(i), ph.shift + m_map.observationPose(i), true);
        }
    }
}

void Trajectory::setOdometryPrior(const OdometryPrior& prior)
{
    m_prior = prior;
    recomputePrior();
}

double Trajectory::priorTerm(std::size_t i) const
{
    return priorTerm(i, m_actions[i]);
}

double Trajectory::priorTerm(std::size_t i, const mrpt::poses::CPose3D& action) const
{
    if (i == 0 || !m_prior.enabled())
    {
        return 0.0;
    }
    if (m_prior.covariance == PriorCovariance::Egomotion)
    {
        return m_prior.cost(action, m_reference[i], m_reference_info[i]);
    }
    // a_i spans the frames of element i-1 (from its first frame to element i's).
    return m_prior.cost(action, m_reference[i], m_frames[i - 1].size());
}

double Trajectory::priorEnergyOf(const std::vector<mrpt::poses::CPose3D>& actions) const
{
    if (actions.size() != m_actions.size())
    {
        throw std::invalid_argument(
            "Trajectory::priorEnergyOf: got " + std::to_string(actions.size()) +
            " actions for N = " + std::to_string(m_actions.size()));
    }
    double sum = 0.0;
    for (std::size_t i = 0; i < actions.size(); ++i)
    {
        sum += priorTerm(i, dof() == 3 ? planarAction(actions[i]) : actions[i]);
    }
    return sum;
}

void Trajectory::recomputePrior()
{
    m_prior_terms.resize(m_actions.size());
    for (std::size_t i = 0; i < m_actions.size(); ++i)
    {
        m_prior_terms[i] = priorTerm(i);
    }
    m_prior_sum = std::accumulate(m_prior_terms.begin(), m_prior_terms.end(), 0.0);
}

void Trajectory::updatePrior(const std::vector<ActionChange>& changed)
{
    if (!m_prior.enabled())
    {
        return;
    }
    for (const ActionChange& c : changed)
    {
        m_prior_terms[c.index] = priorTerm(c.index);
    }
    // Summed afresh (N is small): no drift, and the same value for the same state.
    m_prior_sum = std::accumulate(m_prior_terms.begin(), m_prior_terms.end(), 0.0);
}

double Trajectory::recomputeEnergy()
{
    recomputePrior();
    const double e0 = m_map.recomputeFromScratch();
    for (auto& ph : m_phase_maps)
    {
        ph.map.recomputeFromScratch();
    }
    return phaseMean(e0) + m_prior_sum;
}

double Trajectory::movePosesFrom(std::size_t first)
{
    m_moves.clear();
    mrpt::poses::CPose3D p = first == 0 ? mrpt::poses::CPose3D() : pose(first - 1);
    for (std::size_t i = first; i < m_actions.size(); ++i)
    {
        p = p + m_actions[i];
        m_moves.push_back({i, p});
    }
    const double e0 = m_map.moveObservations(m_moves);
    for (auto& ph : m_phase_maps)
    {
        m_shifted_moves.resize(m_moves.size());
        for (std::size_t k = 0; k < m_moves.size(); ++k)
        {
            m_shifted_moves[k] = {m_moves[k].index, ph.shift + m_moves[k].pose};
        }
        ph.map.moveObservations(m_shifted_moves);
    }
    return phaseMean(e0);
}

double Trajectory::changeActions(const std::vector<ActionChange>& changes)
{
    if (changes.empty())
    {
        return energy();
    }
    m_undo.clear();
    std::size_t first = m_actions.size();
    for (const ActionChange& c : changes)
    {
        if (c.index >= m_actions.size())
        {
            throw std::out_of_range(
                "Trajectory::changeActions: index " + std::to_string(c.index) +
                " >= N = " + std::to_string(m_actions.size()));
        }
        m_undo.push_back({c.index, m_actions[c.index]});
        m_actions[c.index] = dof() == 3 ? planarAction(c.action) : c.action;
        first = std::min(first, c.index);
    }
    m_undo_valid = true;
    updatePrior(changes);
    return movePosesFrom(first) + m_prior_sum;
}

double Trajectory::setActions(const std::vector<mrpt::poses::CPose3D>& actions)
{
    if (actions.size() != m_actions.size())
    {
        throw std::invalid_argument(
            "Trajectory::setActions: got " + std::to_string(actions.size()) +
            " actions for N = " + std::to_string(m_actions.size()));
    }
    std::vector<ActionChange> all(actions.size());
    for (std::size_t i = 0; i < actions.size(); ++i)
    {
        all[i] = {i, actions[i]};
    }
    return changeActions(all);
}

double Trajectory::revertLastChange()
{
    if (!m_undo_valid)
    {
        throw std::logic_error("Trajectory::revertLastChange: nothing to revert");
    }
    // Undo in reverse so a repeated index gets its oldest value back.
    for (auto it = m_undo.rbegin(); it != m_undo.rend(); ++it)
    {
        m_actions[it->index] = it->action;
    }
    m_undo_valid = false;
    updatePrior(m_undo);
    const double e0 = m_map.canRevert() ? m_map.revertLastMove() : m_map.energy();
    for (auto& ph : m_phase_maps)
    {
        if (ph.map.canRevert())
        {
            ph.map.revertLastMove();
        }
    }
    return phaseMean(e0) + m_prior_sum;
}

void Trajectory::commitChange()
{
    m_undo_valid = false;
    m_map.commitMove();
    for (auto& ph : m_phase_maps)
    {
        ph.map.commitMove();
    }
}

std::size_t Trajectory::frameCount() const
{
    std::size_t n = 0;
    for (const auto& f : m_frames)
    {
        n += f.size();
    }
    return n;
}

std::vector<TimedPose> Trajectory::framePoses() const
{
    std::vector<TimedPose> out;
    out.reserve(frameCount());
    for (std::size_t i = 0; i < m_frames.size(); ++i)
    {
        for (const ElementFrame& f : m_frames[i])
        {
            out.push_back({f.timestamp, f.frame_index, pose(i) + f.T_element_frame});
        }
    }
    return out;
}

}  // namespace emslam::rectify
