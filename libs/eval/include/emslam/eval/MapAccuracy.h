// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/math/TPoint3D.h>

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace emslam::eval
{
/** The true surfaces of a world as a dense cloud of samples (what
 * `emslam-sim --map-gt-out` writes): positions, optionally the surface
 * normal at each sample and the nearest depth at which the camera saw it.
 * \ingroup emslam_eval_grp \sa MapAccuracy */
struct ReferenceSurface
{
    std::vector<mrpt::math::TPoint3Df> points;
    /** Unit normals, one per point, or empty (distances are then to the
     * nearest sample). */
    std::vector<mrpt::math::TPoint3Df> normals;
    /** Nearest camera depth each sample was seen at [m], one per point, or
     * empty (unknown). */
    std::vector<float> seen_range;
    /** Distance between neighbouring samples on a surface [m]; 0: unknown. */
    double spacing{0.0};
};

/** How close a map is to the true surfaces (accuracy) and how much of them
 * it covers (completeness), the two figures of multi-view stereo benchmarks
 * (Seitz et al., CVPR 2006), in metres of the world frame (no alignment: map
 * and truth share the first camera's frame, so drift shows).
 *
 * - **Accuracy**: for each map point, its distance to the true surface: to
 *   the plane of the nearest sample when normals are known (the distance
 *   along the normal, plus whatever the point overshoots the sample's patch
 *   of half-diagonal spacing/√2 sideways: exact inside a surface, whatever
 *   the sampling), else to the nearest sample. Median, 90th percentile and
 *   mean of these distances.
 * - **Completeness**: the share of reference samples with a map point
 *   within `completeness_distance`; also over the samples seen within
 *   `near_range` when seen ranges are known.
 *
 * Percentiles are nearest-rank: the p-th percentile of n sorted values is
 * the value of rank ceil(p n / 100). Queries go through a k-d tree
 * (PointKdTree): O((N + M) log(N + M)).
 * \ingroup emslam_eval_grp */
class MapAccuracy
{
public:
    struct Options
    {
        /** A reference sample is covered if a map point is this close [m].
         * (Default: 0.05) */
        double completeness_distance{0.05};
        /** Completeness is also given over the samples seen at most this far
         * [m]. (Default: 4) */
        double near_range{4.0};
    };

    /** Measures `map` against `reference`. Throws std::invalid_argument if
     * either is empty or the normals / seen ranges do not match the points. */
    static MapAccuracy compute(
        const std::vector<mrpt::math::TPoint3Df>& map,
        const ReferenceSurface& reference,
        const Options& options);
    static MapAccuracy compute(
        const std::vector<mrpt::math::TPoint3Df>& map, const ReferenceSurface& reference)
    {
        return compute(map, reference, Options());
    }

    /** The p-th nearest-rank percentile of `values` (0 < p <= 100; NaN if empty). */
    static double percentile(std::vector<double> values, double p);

    /** The figures as a JSON object. */
    std::string toJson() const;

    Options options;
    std::size_t map_points{0};        //!< points of the map measured
    std::size_t reference_points{0};  //!< samples of the true surfaces
    double median_m{0};               //!< median distance map → true surface [m]
    double p90_m{0};                  //!< 90th percentile of it [m]
    double mean_m{0};                 //!< mean of it [m]
    /** Share of reference samples within completeness_distance of the map [0, 1]. */
    double completeness{0};
    /** The same over the samples seen within near_range; NaN without seen ranges. */
    double completeness_near{std::numeric_limits<double>::quiet_NaN()};
    std::size_t near_reference_points{0};  //!< samples seen within near_range
};

}  // namespace emslam::eval
