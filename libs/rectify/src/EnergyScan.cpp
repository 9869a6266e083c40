// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/rectify/EnergyScan.h>

#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

namespace emslam::rectify
{
namespace
{
using Move = emslam::CEntropyVoxelMap::ObservationMove;

constexpr double NOT_A_NUMBER = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> v)
{
    if (v.empty())
    {
        return NOT_A_NUMBER;
    }
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/** The observations of a trajectory placed once at given poses, on each grid
 * phase: a segment is moved, its energy read, and the move undone, so every
 * evaluation starts from the same map and costs only the moved elements. */
class PhasedMaps
{
public:
    PhasedMaps(const Trajectory& t, const std::vector<mrpt::poses::CPose3D>& poses, int phases)
    {
        const double cell = t.map().creationOptions().cell_size;
        for (int k = 0; k < phases; ++k)
        {
            // Built as entropyAtElementPoses() builds it, so E(0) is the same number.
            m_shifts.push_back(Trajectory::gridPhaseShift(k, phases, cell));
            m_maps.emplace_back(t.map().creationOptions(), t.map().insertionOptions);
            for (std::size_t i = 0; i < t.size(); ++i)
            {
                m_maps.back().insertWeightedCloud(
                    t.map().observationCloud(i), m_shifts.back() + poses[i], true);
            }
        }
    }

    double energy() const
    {
        double sum = 0;
        for (const auto& m : m_maps)
        {
            sum += m.energy();
        }
        return sum / static_cast<double>(m_maps.size());
    }

    /** The energy with `moves` applied; the maps are left as they were. */
    double energyWith(const std::vector<Move>& moves)
    {
        double sum = 0;
        for (std::size_t k = 0; k < m_maps.size(); ++k)
        {
            m_shifted.resize(moves.size());
            for (std::size_t i = 0; i < moves.size(); ++i)
            {
                m_shifted[i] = {moves[i].index, m_shifts[k] + moves[i].pose};
            }
            sum += m_maps[k].moveObservations(m_shifted);
            m_maps[k].revertLastMove();
        }
        return sum / static_cast<double>(m_maps.size());
    }

private:
    std::vector<mrpt::poses::CPose3D> m_shifts;
    std::vector<emslam::CEntropyVoxelMap> m_maps;
    std::vector<Move> m_shifted;  //!< scratch
};

/** Offset of the lowest energy (ties: the one nearest 0), curvature and slope. */
void summariseLine(EnergyScanLine& line, std::size_t zero, double step)
{
    std::size_t best = zero;
    for (std::size_t j = 0; j < line.energies.size(); ++j)
    {
        const double e = line.energies[j], b = line.energies[best];
        if (e < b || (e == b && std::abs(line.offsets[j]) < std::abs(line.offsets[best])))
        {
            best = j;
        }
    }
    line.argmin_offset = line.offsets[best];
    line.min_energy = line.energies[best];
    const double e0 = line.energies[zero];
    const double ep = line.energies[zero + 1], em = line.energies[zero - 1];
    line.curvature = (ep + em - 2.0 * e0) / (step * step);
    line.slope = (ep - em) / (2.0 * step);
}

EnergyScanSummary summarise(const std::vector<EnergyScanLine>& lines, int dof)
{
    EnergyScanSummary s;
    s.lines = lines.size();
    std::vector<double> translation, rotation;
    std::size_t at_truth = 0;
    for (const auto& l : lines)
    {
        at_truth += l.truthIsMinimum() ? 1 : 0;
        (l.isRotation() ? rotation : translation).push_back(std::abs(l.argmin_offset));
    }
    s.lines_at_truth = at_truth;
    s.fraction_at_truth =
        lines.empty() ? NOT_A_NUMBER : static_cast<double>(at_truth) / lines.size();
    s.median_abs_argmin_translation_m = median(translation);
    s.median_abs_argmin_rotation_rad = median(rotation);
    for (const int d : actionDimensions(dof))
    {
        EnergyScanDimension dim;
        dim.dimension = d;
        std::vector<double> argmins, curvatures;
        std::size_t d_at_truth = 0;
        for (const auto& l : lines)
        {
            if (l.dimension == d)
            {
                argmins.push_back(std::abs(l.argmin_offset));
                curvatures.push_back(l.curvature);
                d_at_truth += l.truthIsMinimum() ? 1 : 0;
            }
        }
        dim.lines = argmins.size();
        dim.fraction_at_truth =
            argmins.empty() ? NOT_A_NUMBER : static_cast<double>(d_at_truth) / argmins.size();
        dim.median_abs_argmin = median(argmins);
        dim.median_curvature = median(curvatures);
        s.dimensions.push_back(dim);
    }
    return s;
}
}  // namespace

void EnergyScanOptions::validate() const
{
    const auto fail = [](const std::string& what)
    { throw std::invalid_argument("EnergyScanOptions: " + what); };
    if (actions < 1)
    {
        fail("actions must be >= 1");
    }
    if (!(translation_step_m >= 0.0) || !std::isfinite(translation_step_m))
    {
        fail("translation_step_m must be >= 0 (0: a quarter of the cell size)");
    }
    if (translation_steps < 1 || rotation_steps < 1)
    {
        fail("translation_steps and rotation_steps must be >= 1");
    }
    if (!(rotation_step_deg > 0.0) || !std::isfinite(rotation_step_deg))
    {
        fail("rotation_step_deg must be > 0");
    }
    if (grid_phases < 0 || grid_phases > 8)
    {
        fail("grid_phases must be in 0..8 (0: the trajectory's)");
    }
}

std::string actionDimensionName(int dimension)
{
    static const char* const names[6] = {"x", "y", "z", "theta_x", "theta_y", "theta_z"};
    if (dimension < 0 || dimension > 5)
    {
        throw std::out_of_range("actionDimensionName: " + std::to_string(dimension));
    }
    return names[dimension];
}

std::vector<int> actionDimensions(int dof)
{
    // Camera frame, y vertical: a planar action is [δx, δz, δθ_y].
    return dof == 3 ? std::vector<int>{0, 2, 4} : std::vector<int>{0, 1, 2, 3, 4, 5};
}

std::vector<std::size_t> energyScanActions(const Trajectory& t, std::size_t count)
{
    std::set<std::size_t> chosen;
    const std::size_t n = t.size();
    if (n > 0 && t.dependsOnGlobalAlignment())
    {
        chosen.insert(0);
    }
    if (n >= 2)
    {
        chosen.insert(1);
        for (std::size_t j = 1; j < count; ++j)
        {
            const double at = 1.0 + static_cast<double>(j) * static_cast<double>(n - 2) /
                                        static_cast<double>(count - 1);
            chosen.insert(static_cast<std::size_t>(std::llround(at)));
        }
        chosen.insert(n / 2);
    }
    return {chosen.begin(), chosen.end()};
}

EnergyScan scanEnergy(
    const Trajectory& t,
    const std::vector<mrpt::poses::CPose3D>& truth_poses,
    const EnergyScanOptions& options)
{
    const auto t_start = std::chrono::steady_clock::now();
    options.validate();
    if (truth_poses.size() != t.size())
    {
        throw std::invalid_argument(
            "scanEnergy: " + std::to_string(truth_poses.size()) + " poses for " +
            std::to_string(t.size()) + " elements");
    }
    const int phases = options.grid_phases == 0 ? t.gridPhases() : options.grid_phases;
    const double step_m = options.translation_step_m > 0
                              ? options.translation_step_m
                              : 0.25 * t.map().creationOptions().cell_size;
    const double step_rad = mrpt::DEG2RAD(options.rotation_step_deg);

    // The truth's actions: a_0 = T_0, a_i = T_{i-1}⁻¹ ⊕ T_i.
    std::vector<mrpt::poses::CPose3D> actions(truth_poses.size());
    for (std::size_t i = 0; i < truth_poses.size(); ++i)
    {
        actions[i] = i == 0 ? truth_poses[0] : truth_poses[i] - truth_poses[i - 1];
    }

    EnergyScan scan;
    PhasedMaps maps(t, truth_poses, phases);
    const double e0 = maps.energy();
    std::size_t evaluations = t.empty() ? 0 : 1;
    std::vector<Move> moves;
    for (const std::size_t k : energyScanActions(t, options.actions))
    {
        const mrpt::poses::CPose3D before = k == 0 ? mrpt::poses::CPose3D() : truth_poses[k - 1];
        for (const int d : actionDimensions(t.dof()))
        {
            EnergyScanLine line;
            line.action = k;
            line.dimension = d;
            line.energy_at_truth = e0;
            const bool rotation = d >= 3;
            const int steps = rotation ? options.rotation_steps : options.translation_steps;
            const double step = rotation ? step_rad : step_m;
            for (int j = -steps; j <= steps; ++j)
            {
                line.offsets.push_back(j * step);
                if (j == 0)
                {
                    line.energies.push_back(e0);
                    continue;
                }
                ActionDelta delta{};
                delta[d] = j * step;
                mrpt::poses::CPose3D a = perturbAction(actions[k], delta);
                if (t.dof() == 3)
                {
                    a = planarAction(a);  // as Trajectory keeps it
                }
                // The changed action moves elements k..N-1: compose the rest again.
                moves.clear();
                mrpt::poses::CPose3D p = before + a;
                moves.push_back({k, p});
                for (std::size_t i = k + 1; i < actions.size(); ++i)
                {
                    p = p + actions[i];
                    moves.push_back({i, p});
                }
                line.energies.push_back(maps.energyWith(moves));
                ++evaluations;
            }
            summariseLine(line, static_cast<std::size_t>(steps), step);
            scan.lines.push_back(std::move(line));
        }
    }
    scan.summary = summarise(scan.lines, t.dof());
    scan.summary.evaluations = evaluations;
    scan.summary.elements = t.size();
    scan.summary.grid_phases = phases;
    scan.summary.energy_at_truth = e0;
    scan.summary.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    return scan;
}

}  // namespace emslam::rectify
