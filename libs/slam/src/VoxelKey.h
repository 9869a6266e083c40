// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cmath>
#include <cstdint>

namespace emslam::slam
{
/** The voxel of a point as one 64-bit key: 21 bits per axis (±10^6 voxels
 * of 1 / inv_voxel metres around the origin), for hash maps of voxels. */
inline std::uint64_t voxelKey(double x, double y, double z, double inv_voxel)
{
    const auto k = [&](double v)
    {
        // floor() by truncation: the x86-64 baseline has no rounding
        // instruction, so std::floor is a library call (5 % of the fusion).
        const double t = v * inv_voxel;
        auto i = static_cast<std::int64_t>(t);
        i -= t < static_cast<double>(i) ? 1 : 0;
        return static_cast<std::uint64_t>(i + (1 << 20)) & 0x1FFFFF;
    };
    return (k(x) << 42) | (k(y) << 21) | k(z);
}
}  // namespace emslam::slam
