// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Trajectory.h>
#include <emslam/slam/IntensityCloud.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::slam
{
/** A 2D occupancy grid of a finished map: what a robot's planner reads
 * (MRPT mrpt::maps::COccupancyGridMap2D; `map_grid.gridmap` and
 * `map_grid.png` of emslam-mapper).
 *
 * - Dense cells hold at least `min_points` map points whose height is in
 *   the band [`min_height`, `max_height`] (above the first camera, up =
 *   −y): obstacles a robot of that height meets; the floor and the ceiling
 *   are outside the band.
 * - From each keyframe's position, rays spread over its horizontal field of
 *   view (`fov_deg`) at an angular step of one cell at `max_range`; each
 *   runs until the first dense cell or `max_range`. Cells a ray went
 *   through are free; the dense cells where rays stopped are occupied: the
 *   surfaces the keyframes saw.
 * - Unknown (0.5): the rest, including dense cells no ray reached. Stereo
 *   depth noise spreads a wall's points along the viewing rays, behind the
 *   wall as much as before it; the ray stops at the side it sees.
 *
 * The grid's X is the first camera's forward (z) and its Y its left (−x),
 * as in map.3Dscene, so the plan is seen from above with up = +Z.
 * \ingroup emslam_slam_grp */
class OccupancyGridBuilder
{
public:
    /** `[OccupancyGridBuilder]` */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of a bad value. */
        void validate() const;

        /** [m] side of a cell; 0: no grid. (Default: 0.1) */
        double cell_size{0.1};
        /** [m] lowest height above the first camera that is an obstacle (a
         * camera 1 m above the floor: 0.2 m above it). (Default: -0.8) */
        double min_height{-0.8};
        /** [m] highest height above the first camera that is an obstacle.
         * (Default: 0.5) */
        double max_height{0.5};
        /** Map points a cell needs to be occupied. (Default: 2) */
        int min_points{2};
        /** [deg] horizontal field of view the keyframes see free space in.
         * (Default: 70) */
        double fov_deg{70.0};
        /** [m] how far a keyframe's rays reach. (Default: 6) */
        double max_range{6.0};
    };

    /** What build() counted. */
    struct Stats
    {
        /** Cells of the grid, of them occupied, and free (seen through). */
        ///@{
        std::size_t cells{0}, occupied{0}, free{0};
        ///@}
        std::size_t band_points{0};  //!< map points inside the height band
        std::size_t rays{0};         //!< free-space rays cast
    };

    /** A builder with the parameters `p` (validated). */
    explicit OccupancyGridBuilder(const TParameters& p);

    /** The grid of `cloud` (world frame = the first camera's) seen from the
     * keyframe poses `keyframes` (T_world_frame). Throws std::invalid_argument
     * if cell_size is 0 or the grid would exceed 100 million cells. */
    mrpt::maps::COccupancyGridMap2D build(
        const IntensityCloud& cloud, const std::vector<emslam::rectify::TimedPose>& keyframes);

    /** What the last build() counted. */
    const Stats& stats() const { return m_stats; }

    /** Grid coordinates (X forward, Y left) of a point of the map frame. */
    static mrpt::math::TPoint2D gridPoint(const mrpt::math::TPoint3D& p) { return {p.z, -p.x}; }

private:
    /** The grid points of the map points inside the height band. */
    std::vector<mrpt::math::TPoint2D> bandPoints(const IntensityCloud& cloud) const;
    /** An unknown grid holding `band` and the keyframes, with a margin. */
    mrpt::maps::COccupancyGridMap2D emptyGrid(
        const std::vector<mrpt::math::TPoint2D>& band,
        const std::vector<emslam::rectify::TimedPose>& keyframes) const;

    TParameters m_p;
    Stats m_stats;
};

}  // namespace emslam::slam
