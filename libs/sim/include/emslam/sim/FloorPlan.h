// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/sim/SurfaceSampler.h>

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <vector>

namespace emslam::sim
{
/** Where the true floor plan is taken from: the band of heights and the
 * range of the grid it is compared with (the mapper's [OccupancyGridBuilder]).
 * \ingroup emslam_sim_grp \sa floorPlanGrid() */
struct FloorPlanBand
{
    double cell_size{0.1};    //!< [m]
    double min_height{-0.8};  //!< [m] above the first camera (up = its −y)
    double max_height{0.5};   //!< [m]
    double max_range{6.0};    //!< [m] farthest depth a surface counts from
};

/** The true floor plan as an occupancy grid in the convention of the
 * mapper's map_grid.gridmap (slam::OccupancyGridBuilder: grid X = the first
 * camera's forward z, grid Y = its left −x, cells aligned on multiples of
 * the cell size): a cell is occupied (value 0: MRPT cells hold the
 * probability of being free) where a surface sample of `seen`
 * (visibleSurfaces(), first camera's frame) lies inside the height band and
 * was seen at most `max_range` away: the walls and obstacles the trajectory
 * met at the height a robot would; every other cell is free (1). Throws
 * std::invalid_argument on a cell size <= 0, an empty band or no sample in
 * the band. \ingroup emslam_sim_grp */
mrpt::maps::COccupancyGridMap2D floorPlanGrid(
    const std::vector<SurfaceSample>& seen, const FloorPlanBand& band);

}  // namespace emslam::sim
