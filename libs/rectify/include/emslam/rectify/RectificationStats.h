// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <vector>

namespace emslam::rectify
{
/** What one rectification did (the data of the paper's Figs. 17, 20, 24).
 * In AnyTime mode one record covers the attempts between two
 * synchronisations. \ingroup emslam_rectify_grp */
struct RectificationStats
{
    std::size_t elements{0};        //!< N during the rectification
    std::size_t frames{0};          //!< accepted frames in the trajectory
    std::size_t attempts{0};        //!< perturbations evaluated
    std::size_t successes{0};       //!< attempts that lowered the energy
    std::size_t accepted_worse{0};  //!< failures kept anyway (Metropolis-Hastings)
    std::size_t failures{0};        //!< attempts that did not lower the energy
    double energy_before{0.0};      //!< energy when it started
    double energy_after{0.0};       //!< energy of the trajectory it left (the best seen)
    double seconds{0.0};            //!< wall time spent on attempts [s]
    bool converged{false};          //!< ended by NC_max consecutive failures
    /** Of `attempts`, those made on a coarser grid than l_d (`coarse_levels`). */
    std::size_t coarse_attempts{0};
    /** `validate_phases`: the shifted grids did not confirm the gain, so the
     * trajectory went back to where this rectification started. */
    bool rejected_by_validation{false};
    /** Of `failures`, attempts that lowered the energy on the grid but that
     * `confirm_phases`' shifted grids did not confirm. */
    std::size_t unconfirmed{0};
    /** `hold_before_revisit`: the trajectory had not revisited a place, so
     * this rectification made no attempt. */
    bool held_before_revisit{false};
    /** Energy of the trajectory after each attempt (kept or reverted), for
     * plots; 4 bytes per attempt. */
    std::vector<float> energy_trace;
};

}  // namespace emslam::rectify
