// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cstddef>
#include <string>

namespace emslam::eval
{
/** Occupied cells of an estimated occupancy grid against a true floor plan
 * of the same cell size (`emslam-sim --grid-gt-out`): precision, recall and
 * F1 of the occupied cells (MRPT's cell value, the probability of being
 * free, below 0.5).
 *
 * A cell matches if the other grid has an occupied cell within `tolerance`
 * cells (Chebyshev distance, default 1: the 3 x 3 neighbourhood). Exact
 * comparison (tolerance 0) is ill-posed for a wall that lies on a cell
 * boundary, as every wall of a building generated on a 2 m plan does at
 * 10 cm cells: a millimetre decides which of two cells it falls in, in the
 * truth as in the map. One cell also lets a wall thickened by stereo noise
 * by one cell on either side count once. Cells are paired by the position of
 * their centres, so the grids may have different extents; estimated cells
 * outside the truth's extent are false.
 * \ingroup emslam_eval_grp */
class OccupancyGridAccuracy
{
public:
    /** Compares `estimate` with `truth`. Throws std::invalid_argument if their
     * cell sizes differ by more than 0.1 % or `tolerance` is negative. */
    static OccupancyGridAccuracy compute(
        const mrpt::maps::COccupancyGridMap2D& estimate,
        const mrpt::maps::COccupancyGridMap2D& truth,
        int tolerance = 1);

    /** The figures as a JSON object. */
    std::string toJson() const;

    int tolerance_cells{1};
    double cell_size{0};                //!< [m]
    std::size_t estimated_occupied{0};  //!< occupied cells of the estimate
    std::size_t true_occupied{0};       //!< occupied cells of the truth
    std::size_t estimated_matched{0};   //!< of those of the estimate, near a true one
    std::size_t true_matched{0};        //!< of those of the truth, near an estimated one
    double precision{0};                //!< estimated_matched / estimated_occupied (NaN if none)
    double recall{0};                   //!< true_matched / true_occupied (NaN if none)
    double f1{0};                       //!< 2 P R / (P + R) (NaN if either is)
};

}  // namespace emslam::eval
