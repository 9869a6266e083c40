// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Action.h>
#include <emslam/rectify/RectificationStats.h>
#include <emslam/rectify/RectifierOptions.h>
#include <emslam/rectify/Trajectory.h>

#include <atomic>
#include <cstddef>
#include <random>
#include <vector>

namespace emslam::rectify
{
/** Global rectification by information-driven quasi-random updates (§2.2.3):
 * Metropolis-Hastings over the trajectory's actions.
 *
 * One attempt perturbs S_sel = max(1, round(select_fraction · N)) distinct
 * actions chosen at random — a_0 always when the energy depends on the
 * global alignment (Manhattan / flat-floor terms), never otherwise (the
 * energy is then blind to it, and the world stays the first camera frame) —
 * each component by U(−ε, +ε) (see perturbAction()); with the egomotion's
 * proposals (`proposal` ≠ box) the actions are drawn from their covariances
 * instead, and a_0's turn is capped at l_d / (distance from the first camera
 * to the farthest map point), so that it moves no point by more than a cell;
 * with `confirm_phases`, a success whose draw moves some point by more than
 * `confirm_min_move` cells (with `confirm_all_before_revisit`: any success
 * until the trajectory revisits a place, revisitsAPlace()) must also lower
 * the energy averaged over shifted grids; with `hold_before_revisit` and
 * such an energy, a run before a revisit makes no attempt at all.
 * An attempt that lowers the energy is a success and is kept; otherwise it
 * is a failure, kept with probability p = E_old / E_try (`acceptance =
 * ratio`, the paper's rule) or never (`greedy`). After a success the same
 * change is tried again, since it usually points down a slope. The run ends
 * after NC_max consecutive failures (or `max_attempts`), and leaves the
 * trajectory at the lowest energy seen.
 *
 * With `coarse_levels` L > 0 a run starts on cells of 2^L·l_d and, each time
 * NC_max consecutive failures end a level, goes on one level finer
 * (refine()), down to l_d: coarse cells see misalignments of up to their
 * size (a loop's), fine ones the detail.
 *
 * Deterministic: the same seed, trajectory and call sequence give the same
 * result. Not thread-safe: one thread drives one rectifier.
 * \ingroup emslam_rectify_grp */
class TrajectoryRectifier
{
public:
    /** A rectifier with the options `p` (validated). */
    explicit TrajectoryRectifier(const TRectifierOptions& p = {});

    /** Rectifies to convergence (see the class comment). `stop`, if given,
     * is polled between attempts and ends the run early. */
    RectificationStats rectify(Trajectory& t, const std::atomic<bool>* stop = nullptr);

    /** @name Step-wise interface (AnyTime)
     * begin() once, attempt() any number of times, finish() at the end: the
     * trajectory then holds the best state seen since begin(). */
    /** @{ */
    /** Starts a run on `t` at the coarsest level: the energy is recomputed
     * from scratch, the best state is the current one, the failure count is 0. */
    void begin(Trajectory& t, RectificationStats& s);
    /** One attempt; returns true on success. */
    bool attempt(Trajectory& t, RectificationStats& s);
    /** After NC_max failures on a coarse level: keeps its best state and goes
     * on one level finer (failure count 0); false at l_d (the run is over). */
    bool refine(Trajectory& t);
    /** Restores the best state seen, returns to l_d, applies
     * `validate_phases` and fills `s.energy_after`. */
    void finish(Trajectory& t, RectificationStats& s);
    /** Consecutive failed attempts (INC): ≥ NC_max means "map stable". */
    int consecutiveFailures() const { return m_consecutive_failures; }
    /** @} */

    /** The options it runs with. */
    const TRectifierOptions& params() const { return m_p; }

private:
    struct Perturbation
    {
        std::size_t index{0};
        ActionDelta delta{};
    };
    void drawPerturbation(const Trajectory& t);
    /** For each action a_i, a bound on the distance from element i's origin
     * to any point of elements i..N-1: the lever arm of a turn of a_i. */
    static std::vector<double> downstreamReach(const Trajectory& t);
    /** A bound on how far the drawn change (m_change) moves any map point:
     * the largest |δt| + |δθ| · reach of its actions (0 without m_reach). */
    double largestMove() const;
    /** The energy averaged over `phases` shifted grids, plus the prior, of
     * `t` with `actions`. */
    static double shiftedGridsEnergy(
        const Trajectory& t, const std::vector<mrpt::poses::CPose3D>& actions, int phases);
    /** shiftedGridsEnergy() over `confirm_phases` grids, with grid 0's
     * entropy (`grid_entropy`, the trajectory's own) given. */
    double confirmationEnergy(
        const Trajectory& t,
        const std::vector<mrpt::poses::CPose3D>& actions,
        double grid_entropy) const;
    /** Puts `t` back to the best state seen since the level started
     * (non-greedy acceptance only). */
    void restoreBestState(Trajectory& t);
    /** Keeps the best state seen (non-greedy acceptance) and moves `t` to
     * `level`; the energy, best state and failure count start afresh there. */
    void startLevel(Trajectory& t, int level);

    TRectifierOptions m_p;
    std::mt19937_64 m_rng;
    std::vector<Perturbation> m_change;     //!< the attempt being tried
    bool m_reuse{false};                    //!< m_change was a success: try it again
    std::vector<std::size_t> m_indices;     //!< scratch: the selection
    bool m_coherent{false};                 //!< the last draw was a coherent run (they alternate)
    std::vector<std::size_t> m_candidates;  //!< scratch: the selection's pool
    std::vector<Trajectory::ActionChange> m_changes;  //!< scratch
    /** True if the phase-averaged energy (entropy over `validate_phases`
     * grids plus the prior) of `t` is below that at m_start. */
    bool shiftedGridsConfirm(const Trajectory& t) const;

    std::vector<mrpt::poses::CPose3D> m_best;
    std::vector<mrpt::poses::CPose3D> m_start;  //!< the actions at begin()
    std::vector<double> m_reach;  //!< downstreamReach() at begin(), when a cap or check needs it
    /** confirm_phases: the actions before the attempt being checked, and
     * the shifted-grids energy of the current state while it is known. */
    std::vector<mrpt::poses::CPose3D> m_before;
    double m_shifted_energy{0.0};
    bool m_shifted_known{false};
    /** confirm_all_before_revisit: the trajectory has not come back to a
     * place yet (revisitsAPlace() at begin()), so every success is checked. */
    bool m_confirm_all{false};
    /** hold_before_revisit: no revisit yet, so this run makes no attempt. */
    bool m_hold{false};
    double m_best_energy{0.0};
    double m_energy{0.0};
    int m_consecutive_failures{0};
};

}  // namespace emslam::rectify
