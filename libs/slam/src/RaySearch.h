// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include "VoxelTable.h"

#include <mrpt/math/TPoint3D.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace emslam::slam
{
/** A point's weight in the fusion, 1/σ²; a σ of 0 counts as 1 mm. */
inline double inverseVariance(double sigma)
{
    const double s = std::max(sigma, 1e-3);
    return 1.0 / (s * s);
}

/** A point that is not fused (no voxel). */
constexpr std::uint32_t NO_VOXEL = ~std::uint32_t{0};

/** What the search along the rays reads of the points (FusedPointCloud's). */
struct RayPoints
{
    const std::vector<mrpt::math::TPoint3Df>& points;  //!< world frame
    const std::vector<float>& sigma;                   //!< along each ray [m]
    const std::vector<std::uint32_t>& view;            //!< index in origins
    const std::vector<mrpt::math::TPoint3D>& origins;  //!< camera positions
    double voxel_size;                                 //!< [m]
};

/** FusedPointCloud's fusion along the rays: `passes` times, each point
 * (`slot[i]`: its voxel's slot in `voxels`, or NO_VOXEL: unused) joins the
 * voxel along its own ray, within ±2σ, that holds the most evidence (the
 * largest Σ 1/σ² of the points the last pass put there), nearer ones
 * preferred softly by exp(−t²/2(2σ)²), its own scored at t = 0. `voxels`
 * holds the voxel of every used point; the slots of the result index it.
 * Runs on as many threads as the machine has cores; the result does not
 * depend on their number. */
void assignAlongRays(
    const RayPoints& rays, const VoxelTable& voxels, std::vector<std::uint32_t>& slot, int passes);

}  // namespace emslam::slam
