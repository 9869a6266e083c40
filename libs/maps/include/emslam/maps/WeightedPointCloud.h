// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/math/TPoint3D.h>

#include <vector>

namespace emslam::maps
{
/** A point cloud whose points carry weights (number of original points each
 * one stands for), in the frame of the observation that produced it.
 * \ingroup emslam_maps_grp \sa simplifyCloud, CEntropyVoxelMap::insertWeightedCloud */
struct WeightedPointCloud
{
    std::vector<mrpt::math::TPoint3Df> points;  //!< coordinates [m]
    std::vector<float> weights;                 //!< one per point, > 0

    /** Number of points. */
    std::size_t size() const { return points.size(); }
    /** No point. */
    bool empty() const { return points.empty(); }
    /** Σ weights. */
    double totalWeight() const;
    /** True if every weight is an integer in [0, 2^24] (e.g. point counts). */
    bool hasIntegralWeights() const;
    /** Appends one point. */
    void push_back(const mrpt::math::TPoint3Df& p, float w)
    {
        points.push_back(p);
        weights.push_back(w);
    }
};

/** Observation simplification of §2.2.2: divides the bounding box of the
 * cloud into a grid of cells of size `cell_size` (l_d) anchored at the box's
 * minimum corner, and returns one point per occupied cell at the (weighted)
 * centroid of its points, weighted by their number (or the sum of `weights`
 * if given; `weights` may be empty = all 1). Output order: by cell, x major.
 * Throws if cell_size ≤ 0 or weights.size() mismatches.
 * \ingroup emslam_maps_grp */
WeightedPointCloud simplifyCloud(
    const std::vector<mrpt::math::TPoint3Df>& points,
    const std::vector<float>& weights,
    double cell_size);

/** Sorts the points (and weights) by their cell floor(p / cell_size), x
 * major: spatially coherent order makes histogram updates cache friendly.
 * \ingroup emslam_maps_grp */
void sortByCell(WeightedPointCloud& cloud, double cell_size);

/** Same for an already weighted cloud. \ingroup emslam_maps_grp */
inline WeightedPointCloud simplifyCloud(const WeightedPointCloud& cloud, double cell_size)
{
    return simplifyCloud(cloud.points, cloud.weights, cell_size);
}

}  // namespace emslam::maps
