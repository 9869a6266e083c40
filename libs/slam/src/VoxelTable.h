// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace emslam::slam
{
/** The voxels holding points, as voxelKey()s in one open-addressing table
 * (linear probing, power-of-two size, at most three quarters full), each at
 * a slot that indexes dense arrays of per-voxel values: the search along the
 * rays of FusedPointCloud looks up tens of voxels per point, and
 * std::unordered_map's node per key made that most of the fusion's time.
 * Keys have 63 bits, so EMPTY marks a free slot. Not maps::WeightedHistogram:
 * its entropy bookkeeping and load of at most 1/2 raised the KITTI run's peak
 * RSS from 216 to 230 MB (same map). */
class VoxelTable
{
public:
    static constexpr std::uint64_t EMPTY = ~std::uint64_t{0};
    static constexpr std::size_t NONE = ~std::size_t{0};

    /** Room for `expected` voxels before growing. */
    explicit VoxelTable(std::size_t expected)
    {
        std::size_t capacity = 16;
        while (3 * capacity < 4 * expected)
        {
            capacity *= 2;
        }
        m_keys.assign(capacity, EMPTY);
        m_mask = capacity - 1;
    }

    /** Adds `key` (if new); returns its slot, valid until the table grows:
     * grown() counts that. */
    std::size_t insert(std::uint64_t key)
    {
        if (4 * (m_used + 1) > 3 * m_keys.size())
        {
            grow();
        }
        std::size_t i = firstSlot(key);
        while (m_keys[i] != key && m_keys[i] != EMPTY)
        {
            i = (i + 1) & m_mask;
        }
        if (m_keys[i] == EMPTY)
        {
            m_keys[i] = key;
            ++m_used;
        }
        return i;
    }

    /** The slot holding `key`, or NONE. */
    std::size_t slotOf(std::uint64_t key) const
    {
        for (std::size_t i = firstSlot(key);; i = (i + 1) & m_mask)
        {
            if (m_keys[i] == key)
            {
                return i;
            }
            if (m_keys[i] == EMPTY)
            {
                return NONE;
            }
        }
    }

    /** Asks the cache for `key`'s first slot ahead of slotOf(key): a lookup
     * is mostly a cache miss, so several can be fetched together. */
    void prefetch(std::uint64_t key) const { __builtin_prefetch(&m_keys[firstSlot(key)]); }

    std::size_t capacity() const { return m_keys.size(); }
    std::uint64_t keyAt(std::size_t slot) const { return m_keys[slot]; }
    /** How many times the table grew (slots taken before then moved). */
    std::size_t grown() const { return m_grown; }

private:
    std::size_t firstSlot(std::uint64_t key) const
    {
        // Fibonacci hashing: neighbouring voxels land far apart.
        return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 32) & m_mask;
    }

    void grow()
    {
        VoxelTable bigger(m_keys.size());
        for (const std::uint64_t key : m_keys)
        {
            if (key != EMPTY)
            {
                bigger.insert(key);
            }
        }
        bigger.m_grown = m_grown + 1;
        *this = std::move(bigger);
    }

    std::vector<std::uint64_t> m_keys;
    std::size_t m_mask{0}, m_used{0}, m_grown{0};
};

}  // namespace emslam::slam
