// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/OdometryPrior.h>

#include <mrpt/config/CLoadableOptions.h>

#include <cstdint>
#include <string>

namespace emslam::rectify
{
/** How a Metropolis-Hastings attempt that does not lower the energy is treated. */
enum class Acceptance : std::uint8_t
{
    /** The paper's rule (§2.2.3): accepted with probability p = E_old / E_try. */
    Ratio = 0,
    /** Only attempts that lower the energy are kept (a pure descent). */
    Greedy
};

/** When rectification runs (§2.2.3). */
enum class RectificationMode : std::uint8_t
{
    /** Every S_rec accepted frames, to convergence, while the robot waits. */
    Serial = 0,
    /** Continuously in a second thread, synchronised every S_buf frames. */
    AnyTime
};

/** How an attempt draws the change of each selected action. */
enum class ProposalShape : std::uint8_t
{
    /** The paper's box: U(−ε, +ε) per component (§2.2.3). */
    Box = 0,
    /** Gaussian with the egomotion's covariance of that action (times
     * proposal_scale²): large where the images left the action uncertain,
     * small where they pinned it down. a_0 keeps the box. */
    Covariance,
    /** Like Covariance, but every other attempt bends the trajectory: a run
     * of S_sel consecutive actions gets the same draw (from the first one's
     * covariance), so the segment after it turns and shifts coherently, as
     * closing a loop needs, for the prior cost of independent draws. */
    Coherent
};

/** Parameters of the global rectification, section `[Rectifier]` (paper
 * §2.2.3-2.2.4). The defaults are the shipped tuning; the paper's own values
 * (§3.2) are config/mapper/paper.ini. The degrees of freedom (3DOF [δx, δz, δθ_y] or 6DOF)
 * follow the map's energy (`[EntropyVoxelMap]` `energy` / `dof`).
 *
 * \code
 * [Rectifier]
 * eps_xyz          = 0.05    ; ε of each translation component [m]
 * eps_rot_deg      = 3       ; ε of each rotation component [deg]
 * select_fraction  = 0.10    ; S_sel: fraction of the N actions perturbed per attempt
 * nc_max           = 50      ; NC_max: consecutive failed attempts that end a rectification
 * max_attempts     = 20000   ; safety cap per rectification (0: none)
 * min_improvement  = 1e-5    ; a success lowers E by more than this fraction of E
 * acceptance       = greedy  ; greedy | ratio (the paper: p = E_old / E_try)
 * reuse_success    = true    ; after a success, try the same change again
 * rectify_every    = 25      ; S_rec: serial, accepted frames between rectifications (0: never)
 * mode             = serial  ; serial | anytime
 * buffer_size      = 10      ; S_buf: AnyTime, frames buffered between synchronisations
 * n_max            = 60      ; N_max: compress the trajectory when N exceeds it (0: never)
 * seed             = 1       ; random seed (serial mode repeats exactly)
 * vertical_band    = false   ; keep only points with band_min_y <= y <= band_max_y
 * band_min_y       = -1.5    ; [m] camera frame, y down (above the camera is < 0)
 * band_max_y       = 0.8     ; [m]
 * prior_weight     = 0.001   ; odometry prior (0: off, the paper's energy)
 * prior_sigma_xyz  = 0.02    ; [m] per accepted step
 * prior_sigma_rot_deg = 0.5  ; [deg] per accepted step
 * prior_covariance = egomotion ; fixed (the sigmas above) | egomotion (Dpp curvature)
 * proposal         = covariance ; box (the paper's ε) | covariance | coherent (egomotion's)
 * proposal_scale   = 1       ; σ multiplier of the covariance proposal
 * experimental_grid_phases = 1 ; entropy averaged over shifted voxel grids (1: the paper)
 * coarse_levels    = 0       ; each rectification first runs on cells 2^L..2 l_d (0: the paper)
 * validate_phases  = 0       ; keep a rectification only if K shifted grids agree (0: the paper)
 * confirm_phases   = 0       ; a success that moves a point > a cell needs K shifted grids (0: off)
 * confirm_min_move = 1       ; [cells] the move beyond which confirm_phases checks (0: all)
 * confirm_all_before_revisit = false ; confirm_phases checks every success until a revisit
 * hold_before_revisit = false ; no change at all until a revisit (energies blind to a_0)
 * threads          = 2       ; threads of one attempt's map update: 1 | 2 (same results)
 * chains           = 1       ; serial: K independent searches, poses averaged (1: the paper)
 * \endcode
 *
 * `vertical_band` is an option beside the paper: for a 3DOF robot (fixed
 * camera height) it drops floor and ceiling points, whose projection on the
 * XZ plane carries no alignment information but rewards folding corridors
 * onto each other (Exp. 11-12 on dense clouds; see doc/rectify.md).
 * `prior_weight` > 0 adds an OdometryPrior to the entropy, also beside the paper.
 * \ingroup emslam_rectify_grp */
struct TRectifierOptions : public mrpt::config::CLoadableOptions
{
    /** Reads the `[Rectifier]` keys of section `s` of `c`; absent keys keep their value. */
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    /** Writes every key to section `s` of `c`. */
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /** Throws std::invalid_argument naming the `[Rectifier]` key of a bad value. */
    void validate() const;

    double eps_xyz{0.05};          //!< ε_x = ε_y = ε_z [m] (Default: 0.05)
    double eps_rot_deg{3.0};       //!< ε_θx = ε_θy = ε_θz [deg] (Default: 3)
    double select_fraction{0.10};  //!< S_sel as a fraction of N, in (0, 1] (Default: 0.10)
    int nc_max{50};                //!< NC_max (Default: 50)
    int max_attempts{20000};       //!< cap per rectification; 0: none (Default: 20000)
    /** Relative energy drop below which an attempt counts as a failure:
     * without it, noise-level gains keep resetting INC and a run may never
     * reach NC_max. (Default: 1e-5) */
    double min_improvement{1e-5};
    Acceptance acceptance{Acceptance::Greedy};  //!< (Default: greedy; see doc/rectify.md)
    bool reuse_success{true};                   //!< repeat a successful change (Default: true)
    /** S_rec; 0 (serial mode only): never rectify, the trajectory and its
     * map are only built (egomotion only). (Default: 25) */
    int rectify_every{25};
    RectificationMode mode{RectificationMode::Serial};  //!< (Default: serial)
    int buffer_size{10};                                //!< S_buf (Default: 10)
    int n_max{60};                                      //!< N_max; 0: no compression (Default: 60)
    std::uint64_t seed{1};                              //!< (Default: 1)
    bool vertical_band{false};  //!< filter points by camera-frame y (Default: false)
    double band_min_y{-1.5};    //!< [m] (Default: -1.5)
    double band_max_y{0.8};     //!< [m] (Default: 0.8)
    /** OdometryPrior weight [nats]; 0: off, the paper's energy. Shipped on:
     * where the entropy is flat (a corridor, a straight drive) it keeps the
     * actions near the egomotion's. (Default: 0.001) */
    double prior_weight{0.001};
    double prior_sigma_xyz{0.02};     //!< [m] one accepted step (Default: 0.02)
    double prior_sigma_rot_deg{0.5};  //!< [deg] one accepted step (Default: 0.5)
    /** Where the prior's covariance comes from: each step's own
     * (egomotion), or the sigmas above (fixed). (Default: egomotion) */
    PriorCovariance prior_covariance{PriorCovariance::Egomotion};
    /** Covariance: a box move costs tens of σ under the prior; the paper's
     * box is `box`. (Default: covariance) */
    ProposalShape proposal{ProposalShape::Covariance};
    double proposal_scale{1.0};  //!< (Default: 1)
    /** Grid phases the entropy is averaged over (Trajectory::setGridPhases());
     * 1: the paper's single voxel grid. Experimental: with 4, the 3DOF
     * Manhattan energy (Exp. 12) closed the hall and the corridors with a
     * smaller gap and ATE on every seed, at 3-4x the time per call, and the
     * other energies got no better (doc/notes/2026-12-01-grid-phases.md).
     * (Default: 1) */
    int experimental_grid_phases{1};
    /** Coarse to fine: each rectification first runs to convergence on
     * cells of 2^L·l_d, then 2^(L-1)·l_d, ..., then l_d; 0: only l_d, the
     * paper (Default: 0) */
    int coarse_levels{0};
    /** K ≥ 2: a rectification is kept only if it also lowers the energy
     * averaged over K voxel grids shifted by k/K of a cell (k = 0..K-1);
     * otherwise the trajectory goes back to where the rectification started.
     * A gain that only one grid sees is the grid's, not the map's. 0: off,
     * the paper (Default: 0) */
    int validate_phases{0};
    /** K ≥ 2: a success whose draw moves some map point by more than a cell
     * (a long element's composed covariance can draw metres) is kept only if
     * it also lowers the energy averaged over K shifted grids; otherwise it
     * counts as a failure. A jump onto a look-alike place that one grid
     * favours is refused; moves within a cell are not checked. 0: off, the
     * paper (Default: 0) */
    int confirm_phases{0};
    /** [cells of l_d] confirm_phases checks the successes whose draw moves
     * some map point by more than this; 0: every success. A noise-level
     * gain of a small move is as much the grid's as that of a long one
     * (doc/rectify.md, "Confirming every success"). (Default: 1) */
    double confirm_min_move{1.0};
    /** With an energy blind to the global alignment (Exp. 8, 11): until the
     * trajectory comes back to a place it saw (revisitsAPlace(), at the
     * start of each rectification), confirm_phases checks every success,
     * whatever its move. Before a revisit such an energy only re-measures
     * what the egomotion measured between neighbouring frames, and a gain
     * that the shifted grids do not share is noise. After it, only moves
     * beyond confirm_min_move. Energies that anchor a_0 (Exp. 9, 10, 12)
     * measure the orientation against the world's structure from the first
     * frame on and are not held back (doc/rectify.md, "Confirming every
     * success before a revisit"). (Default: false) */
    bool confirm_all_before_revisit{false};
    /** With an energy blind to the global alignment (Exp. 8, 11): no
     * rectification at all until the trajectory comes back to a place it saw
     * (revisitsAPlace(), at the start of each rectification); the trajectory
     * stays the egomotion's. Stronger than confirm_all_before_revisit: on an
     * open path such an energy can only re-measure, through a voxel grid,
     * what the egomotion measured between neighbouring frames, and even
     * gains that shifted grids confirm left the river bed a few mm worse
     * (doc/rectify.md, "Holding still before a revisit"). Energies that
     * anchor a_0 (Exp. 9, 10, 12) ignore it. (Default: false) */
    bool hold_before_revisit{false};
    /** Threads of one attempt's map update, 1 or 2: with 2, when the energy
     * has the 3D term and marginal ones (Exp. 9, 10) and an attempt moves
     * enough points, the moved clouds are binned in two halves and the 3D
     * histogram and the marginal ones are updated side by side
     * (IncrementalEntropyGrid::setThreads()). The results are the same. In
     * AnyTime mode the second thread competes with the egomotion's.
     * (Default: 2) */
    int threads{2};
    /** K independent serial rectifications (seeds seed..seed+K-1) whose
     * trajectories are averaged pose by pose (AveragedChainsRectification);
     * serial mode only; each rectification costs K times as much. 1: one
     * search, the paper. (Default: 1) */
    int chains{1};

    /** The prior these options describe. */
    OdometryPrior odometryPrior() const
    {
        return OdometryPrior{prior_weight, prior_sigma_xyz, prior_sigma_rot_deg, prior_covariance};
    }
};

/** INI names: `ratio`, `greedy`. */
std::string toString(Acceptance a);
/** INI names: `serial`, `anytime`. */
std::string toString(RectificationMode m);
/** INI names: `box`, `covariance`, `coherent`. */
std::string toString(ProposalShape p);

}  // namespace emslam::rectify
