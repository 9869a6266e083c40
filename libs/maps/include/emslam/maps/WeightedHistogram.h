// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace emslam::maps
{
/** Integer cell coordinates of a voxel (cell index = floor(coordinate / l_d)).
 * \ingroup emslam_maps_grp */
struct CellIndex
{
    std::int32_t x{0};  //!< cell along x
    std::int32_t y{0};  //!< cell along y
    std::int32_t z{0};  //!< cell along z

    /** Same cell. */
    bool operator==(const CellIndex& o) const { return x == o.x && y == o.y && z == o.z; }
    /** Another cell. */
    bool operator!=(const CellIndex& o) const { return !(*this == o); }
};

/** Packs up to three cell coordinates into one 63-bit histogram key (21 bits
 * per axis, i.e. ±2^20 cells: ±157 km at l_d = 0.15 m). Marginal histograms
 * pass 0 for the axes they drop. Coordinates outside the range wrap around
 * (documented limitation, far beyond any map this project builds).
 * \ingroup emslam_maps_grp */
inline std::uint64_t packCellKey(std::int32_t x, std::int32_t y, std::int32_t z)
{
    constexpr std::uint64_t MASK = (std::uint64_t{1} << 21) - 1;
    constexpr std::int64_t OFFSET = std::int64_t{1} << 20;
    return ((static_cast<std::uint64_t>(x + OFFSET) & MASK) << 42) |
           ((static_cast<std::uint64_t>(y + OFFSET) & MASK) << 21) |
           (static_cast<std::uint64_t>(z + OFFSET) & MASK);
}

/** Inverse of packCellKey(). \ingroup emslam_maps_grp */
inline CellIndex unpackCellKey(std::uint64_t key)
{
    constexpr std::uint64_t MASK = (std::uint64_t{1} << 21) - 1;
    constexpr std::int64_t OFFSET = std::int64_t{1} << 20;
    CellIndex c;
    c.x = static_cast<std::int32_t>(static_cast<std::int64_t>((key >> 42) & MASK) - OFFSET);
    c.y = static_cast<std::int32_t>(static_cast<std::int64_t>((key >> 21) & MASK) - OFFSET);
    c.z = static_cast<std::int32_t>(static_cast<std::int64_t>(key & MASK) - OFFSET);
    return c;
}

/** A sparse weighted histogram over integer keys with an O(1) Shannon entropy.
 *
 * The entropy of the normalised histogram p_c = w_c / W is
 * \f[ H = -\sum_c p_c \log p_c = \log W - \frac{1}{W}\sum_c w_c \log w_c , \f]
 * so the class keeps W and the running sum S = Σ w_c log w_c: adding weight
 * to a cell only changes that cell's term, and entropy() is O(1).
 *
 * **Storage.** A flat open-addressing table (linear probing, power-of-two
 * capacity, load factor ≤ 1/2) of {key, weight} slots (16 B); no heap
 * allocation per cell. A cell whose weight drops to zero
 * stays in the table as a zero entry (it contributes nothing and is not
 * counted as occupied) until the next growth, which drops zero entries. This
 * avoids tombstones and keeps removals as cheap as insertions. Compared with
 * `std::unordered_map` (one node allocation per cell, pointer chasing, ~64 B
 * per cell) it avoids an allocation and a pointer chase per access; it uses
 * 16 B per slot (plus a 4 B batch stamp), 40-80 B per occupied cell at load
 * 1/2-1/4.
 *
 * **Batches.** Moving an observation removes its weights from some cells and
 * adds them to others; many cells receive several updates, and many net to
 * zero. Between beginBatch() and endBatch() the updates only change the
 * weights and record each touched slot once (the slot's stamp); endBatch()
 * then updates S once per touched cell. Both paths give the same S up to
 * rounding. The bulk forms (addMany(), addDeferredMany()) prefetch slots a
 * few updates ahead and keep their sums in locals while the table cannot
 * grow. Measured choices (bench_entropy_map, bench_rectify): immediate
 * updates for the 3D histogram (cells mostly touched once); branch-free
 * first-touch records; 16-byte slots without a cached w log w (the old
 * term is recomputed: a table look-up for point counts), because the
 * table of a rectification's 3D histogram outgrows the L2 cache and its
 * cache misses are what a move costs. (Moves of CEntropyVoxelMap
 * now net the marginal updates per cell in dense grids first, then use
 * immediate updates; batches serve insertions and large marginal moves.)
 *
 * **w log w.** Weights are usually integer point counts (§2.2.2): wLogW()
 * takes integer weights below 2^14 from a table, and calls std::log otherwise.
 *
 * \ingroup emslam_maps_grp \sa CEntropyVoxelMap */
class WeightedHistogram
{
public:
    /** Creates an empty histogram with room for about `expected_cells` cells. */
    explicit WeightedHistogram(std::size_t expected_cells = 256);

    /** Removes every cell; keeps the allocated capacity. */
    void clear();

    /** Makes room for `cells` occupied cells without further growth. */
    void reserve(std::size_t cells);

    /** Adds `w` (may be negative, to remove) to the cell `key` and updates the
     * entropy at once. A weight that falls below 1e-12 of its previous value
     * (rounding residue of a removal) is set to exactly zero. */
    void add(std::uint64_t key, double w);

    /** Starts a batch of deferred updates (see class comment).
     * `max_new_cells` is a hint: room for that many new cells is made now
     * (the table still grows inside the batch if needed). */
    void beginBatch(std::size_t max_new_cells);
    /** Adds `w` to cell `key` inside a batch; the entropy is updated by endBatch(). */
    void addDeferred(std::uint64_t key, double w);
    /** One deferred update: weight `w` added to cell `key`. */
    struct Update
    {
        std::uint64_t key{0};  //!< the cell's packed key
        double w{0};           //!< weight added (negative: removed)
    };
    /** addDeferred() for many updates, prefetching the slots a few updates
     * ahead: independent look-ups overlap their cache misses, which is what
     * bounds the cost of moving an observation once the table outgrows L2. */
    void addDeferredMany(const Update* updates, std::size_t n);
    /** add() for many updates (outside a batch), prefetching ahead. Best
     * when most updates hit distinct cells with small integer weights (the 3D
     * histogram), where deferring buys nothing. */
    void addMany(const Update* updates, std::size_t n);
    /** addMany() when every weight involved is an integer: the update
     * weights, and the cells' current weights (e.g. because only integer
     * weights of at most 2^24 were ever added: point counts, §2.2.2). Sums
     * are then exact, so there is no rounding residue to clean, and w log w
     * of weights below 2^14 is one table look-up (no integer test): fewer
     * instructions per update. Same results as addMany() under that
     * precondition (not checked). */
    void addManyIntegral(const Update* updates, std::size_t n);
    /** Ends a batch: updates S, W and the occupied-cell count. */
    void endBatch();

    /** @name Undo record
     * A move that is tried and then rejected (most rectification attempts)
     * used to pay its updates twice: once to apply, once more to apply the
     * opposite. Between beginUndoRecord() and rollback() every changed cell
     * logs its previous weight (sequential writes), so rollback()
     * restores cells, W, S and the occupied count exactly, without hashing
     * or logarithms. A table growth, clear() or bulk rebuild in between
     * cancels the record (slot positions change): canRollback() is then
     * false and the caller undoes the updates itself. */
    /** @{ */
    /** Starts a new record (drops any previous one). */
    void beginUndoRecord();
    /** True if rollback() can restore the state of beginUndoRecord(). */
    bool canRollback() const { return m_undo_valid; }
    /** Restores the state of beginUndoRecord() exactly and ends the record.
     * Cells first created since then stay in the table with zero weight.
     * Throws if !canRollback(). */
    void rollback();
    /** Ends the record without restoring anything. */
    void dropUndoRecord();
    /** @} */

    /** Bulk build (outside a batch): adds positive weights `w` to cells
     * without updating S or the occupied count, prefetching ahead; call
     * recomputeSums() afterwards (entropy() is stale until then). Building
     * from scratch this way evaluates w log w once per cell instead of once
     * per update. */
    void accumulateMany(const Update* updates, std::size_t n);
    /** Recomputes S and the occupied count
     * from the weights (one sweep over the table); W is kept. If `cells_out`
     * is given (room for usedSlots() entries), the sweep also writes the
     * cells with positive weight there. Returns the number of such cells. */
    std::size_t recomputeSums(Update* cells_out = nullptr);
    /** Slots holding a key (≥ occupiedCells(): includes zero-weight cells). */
    std::size_t usedSlots() const { return m_used; }

    /** Weight of a cell (0 if absent). */
    double weight(std::uint64_t key) const;
    /** Total weight W. */
    double totalWeight() const { return m_total; }
    /** Running Σ w log w over the cells. */
    double sumWLogW() const { return m_sum_wlogw; }
    /** Shannon entropy in nats (0 for an empty histogram). */
    double entropy() const { return entropyFrom(m_total, m_sum_wlogw); }
    /** Entropy recomputed by iterating every cell (for checks). */
    double entropyFromScratch() const;
    /** Number of cells with positive weight. */
    std::size_t occupiedCells() const { return m_occupied; }
    /** Bytes used by the table and the batch buffer. */
    std::size_t memoryBytes() const;
    /** Table capacity (number of slots). */
    std::size_t capacity() const { return m_slots.size(); }

    /** Calls `fn(key, weight)` for every cell with positive weight. */
    template <typename FN>
    void forEachCell(FN&& fn) const
    {
        for (const auto& s : m_slots)
        {
            if (s.key != EMPTY_KEY && s.w > 0)
            {
                fn(s.key, s.w);
            }
        }
    }

    /** w·log(w), with 0·log 0 = 0; table look-up for small integer weights. */
    static double wLogW(double w)
    {
        // Zero (emptied cells, frequent) takes the table path too (entry 0 is
        // 0): the branches then follow the weights' type, which is steady.
        // int32, not size_t: a double to unsigned conversion branches on x86.
        if (w >= 0 && w < static_cast<double>(WLOGW_TABLE_SIZE))
        {
            const auto i = static_cast<std::int32_t>(w);
            if (static_cast<double>(i) == w)
            {
                return s_wlogw_table[i];
            }
        }
        return w > 0 ? w * std::log(w) : 0.0;
    }

    /** wLogW() of an integer weight ≥ 0 (`table`: the w log w table, e.g.
     * kept in a local by a loop). */
    static double integralWLogW(double w, const double* table = s_wlogw_table)
    {
        const auto i = static_cast<std::int64_t>(w);
        if (static_cast<std::uint64_t>(i) < WLOGW_TABLE_SIZE)
        {
            return table[i];
        }
        return w > 0 ? w * std::log(w) : 0.0;
    }

    /** H = log W − S/W, 0 when W ≤ 0. */
    static double entropyFrom(double total_weight, double sum_wlogw)
    {
        return total_weight > 0 ? std::log(total_weight) - sum_wlogw / total_weight : 0.0;
    }

private:
    /** addMany() (kIntegral = false) and addManyIntegral() (true). */
    template <bool kIntegral>
    void addManyImpl(const Update* updates, std::size_t n);
    static constexpr std::uint64_t EMPTY_KEY = ~std::uint64_t{0};
    static constexpr std::size_t WLOGW_TABLE_SIZE = std::size_t{1} << 14;
    static const double* wlogwTable();
    static const double* const s_wlogw_table;  //!< = wlogwTable(), set at load time

    struct Slot
    {
        std::uint64_t key{EMPTY_KEY};
        double w{0};
    };
    /** A cell's state before its first change in an undo record. */
    struct UndoRecord
    {
        std::size_t slot{0};
        double w{0};
    };
    /** Room for `n` more undo records; returns where the next one goes.
     * The caller writes them through the pointer (plain stores: a
     * push_back() per update went through memory for the vector's end) and
     * then sets m_undo_count. */
    UndoRecord* reserveUndo(std::size_t n)
    {
        if (m_undo_log.size() < m_undo_count + n)
        {
            m_undo_log.resize(std::max(m_undo_count + n, 2 * m_undo_log.size()));
        }
        return m_undo_log.data() + m_undo_count;
    }
    /** Appends the state of slot `i` to the undo log (when recording). */
    void logSlot(std::size_t i)
    {
        if (m_undo_valid)
        {
            *reserveUndo(1) = {i, m_slots[i].w};
            m_undo_count++;
        }
    }
    /** Cancels the undo record (slot positions are about to change). */
    void cancelUndoRecord()
    {
        m_undo_valid = false;
        m_undo_count = 0;
    }
    struct Touched
    {
        std::size_t slot{0};
        double old_w{0};
    };

    static std::size_t hashSlot(std::uint64_t key, unsigned shift)
    {
        // Fibonacci hashing: the top bits of the product depend on every key
        // bit. (Placing 4x4x4 blocks of cells in nearby slots was tried for
        // cache locality: linear probing then clusters and it was 2x slower.)
        return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> shift);
    }
    std::size_t slotIndexFor(std::uint64_t key) const { return hashSlot(key, m_shift); }
    /** Linear probing from the key's home slot; creates the slot if absent
     * (counted in `used`). Static so the bulk loops can keep their state in
     * locals (registers) instead of members. */
    static std::size_t probeOrInsert(
        Slot* slots, std::size_t mask, unsigned shift, std::uint64_t key, std::size_t& used);
    /** Finds or creates the slot of `key`. */
    std::size_t findOrInsert(std::uint64_t key);
    void rehash(std::size_t new_capacity);
    /** Updates S and the occupied count for slot `s` going from `old_w` to
     * its current weight; refreshes the slot's cached w log w. */
    void accountChange(Slot& s, double old_w);

    std::vector<Slot> m_slots;
    /** Batch epoch of each slot's last touch (beside the slots: only batches
     * read it, and 16-byte slots keep the table of a rectification's 3D
     * histogram half as large). */
    std::vector<std::uint32_t> m_stamps;
    std::vector<Touched> m_touched;  //!< first-touch records; [0, m_touched_count) live
    std::size_t m_touched_count{0};
    std::size_t m_mask{0};
    unsigned m_shift{64};   //!< 64 - log2(capacity)
    std::size_t m_used{0};  //!< slots holding a key (incl. zero-weight ones)
    std::size_t m_occupied{0};
    std::uint32_t m_epoch{0};
    bool m_in_batch{false};
    double m_total{0};
    double m_sum_wlogw{0};
    std::vector<UndoRecord> m_undo_log;  //!< [0, m_undo_count) live, in change order
    std::size_t m_undo_count{0};
    bool m_undo_valid{false};        //!< recording, and rollback() possible
    double m_undo_total{0};          //!< W at beginUndoRecord()
    double m_undo_sum{0};            //!< S at beginUndoRecord()
    std::size_t m_undo_occupied{0};  //!< occupied cells at beginUndoRecord()
};

}  // namespace emslam::maps
