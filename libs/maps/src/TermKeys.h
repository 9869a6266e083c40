// SPDX-License-Identifier: BSD-3-Clause
// Private to emslam_maps (not installed): the histogram keys of the entropy
// terms, shared by IncrementalEntropyGrid and the map's likelihood.
#pragma once

#include <emslam/maps/EntropyEnergy.h>
#include <emslam/maps/WeightedHistogram.h>

#include <cstddef>
#include <cstdint>

namespace emslam::maps::detail
{
/** Axes kept by each term (x, y, z), indexed by EntropyTerm. */
inline constexpr std::int32_t TERM_AXES[NUM_ENTROPY_TERMS][3] = {
    {1, 1, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

/** Key of a cell in the histogram of term `t` (dropped axes set to 0). */
inline std::uint64_t termKey(std::size_t t, const CellIndex& c)
{
    switch (static_cast<EntropyTerm>(t))
    {
        case EntropyTerm::H3D:
            return packCellKey(c.x, c.y, c.z);
        case EntropyTerm::XY:
            return packCellKey(c.x, c.y, 0);
        case EntropyTerm::XZ:
            return packCellKey(c.x, 0, c.z);
        case EntropyTerm::YZ:
            return packCellKey(0, c.y, c.z);
        case EntropyTerm::X:
            return packCellKey(c.x, 0, 0);
        case EntropyTerm::Y:
            return packCellKey(0, c.y, 0);
        case EntropyTerm::Z:
            return packCellKey(0, 0, c.z);
    }
    return 0;
}

/** Indices of the terms set in a mask, in term order. */
struct TermList
{
    std::size_t idx[NUM_ENTROPY_TERMS]{};
    std::size_t n{0};
    explicit TermList(TermMask m)
    {
        for (std::size_t t = 0; t < NUM_ENTROPY_TERMS; t++)
        {
            if (m & (1u << t))
            {
                idx[n++] = t;
            }
        }
    }
};

}  // namespace emslam::maps::detail
