// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/maps/WeightedHistogram.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>

namespace emslam::maps
{
namespace
{
/** Smallest power of two ≥ n (and ≥ 16). */
std::size_t nextPow2(std::size_t n)
{
    std::size_t c = 16;
    while (c < n)
    {
        c <<= 1;
    }
    return c;
}

/** Sets a weight that is only rounding residue of a removal to exactly 0.
 * Branch-free (a multiply by 0 or 1): whether a removal empties a cell is
 * unpredictable, and a branch here mispredicted often in moves. */
inline double cleanResidue(double new_w, double old_w, double delta)
{
    const double scale = std::max(std::abs(old_w), std::abs(delta));
    return new_w * static_cast<double>(std::abs(new_w) > 1e-12 * scale);
}
}  // namespace

const double* WeightedHistogram::wlogwTable()
{
    static const auto table = []()
    {
        std::vector<double> t(WLOGW_TABLE_SIZE, 0.0);
        for (std::size_t i = 1; i < WLOGW_TABLE_SIZE; i++)
        {
            const auto w = static_cast<double>(i);
            t[i] = w * std::log(w);
        }
        return t;
    }();
    return table.data();
}

const double* const WeightedHistogram::s_wlogw_table = WeightedHistogram::wlogwTable();

WeightedHistogram::WeightedHistogram(std::size_t expected_cells)
{
    rehash(nextPow2(2 * std::max<std::size_t>(expected_cells, 8)));
}

void WeightedHistogram::clear()
{
    ASSERTMSG_(!m_in_batch, "WeightedHistogram::clear() inside a batch");
    cancelUndoRecord();
    std::fill(m_slots.begin(), m_slots.end(), Slot{});
    m_used = 0;
    m_occupied = 0;
    m_total = 0;
    m_sum_wlogw = 0;
}

void WeightedHistogram::reserve(std::size_t cells)
{
    ASSERTMSG_(!m_in_batch, "WeightedHistogram::reserve() inside a batch");
    if (2 * cells > m_slots.size())
    {
        rehash(nextPow2(2 * cells));
    }
}

std::size_t WeightedHistogram::memoryBytes() const
{
    return m_slots.capacity() * sizeof(Slot) + m_stamps.capacity() * sizeof(std::uint32_t) +
           m_touched.size() * sizeof(Touched) + m_undo_log.capacity() * sizeof(UndoRecord);
}

void WeightedHistogram::rehash(std::size_t new_capacity)
{
    cancelUndoRecord();
    // Keep only cells with weight (growth is also the garbage collection of
    // zero-weight entries left by removals), plus, inside a batch, the cells
    // the batch touched: their stamps and Touched records must stay valid.
    const auto keep = [this](std::size_t i)
    {
        const Slot& s = m_slots[i];
        return s.key != EMPTY_KEY && (s.w > 0 || (m_in_batch && m_stamps[i] == m_epoch));
    };
    std::size_t live = 0;
    for (std::size_t i = 0; i < m_slots.size(); i++)
    {
        live += keep(i) ? 1 : 0;
    }
    new_capacity = std::max(new_capacity, nextPow2(2 * live + 2));

    std::vector<Slot> old_slots;
    std::vector<std::size_t> remap;  // old slot -> new slot (batch only)
    for (std::size_t i = 0; i < m_slots.size(); i++)
    {
        if (!keep(i))
        {
            m_slots[i].key = EMPTY_KEY;
        }
    }
    old_slots.swap(m_slots);
    std::vector<std::uint32_t> old_stamps;
    old_stamps.swap(m_stamps);
    m_slots.assign(new_capacity, Slot{});
    m_stamps.assign(new_capacity, 0);
    m_mask = new_capacity - 1;
    m_shift = 64;
    for (std::size_t c = new_capacity; c > 1; c >>= 1)
    {
        m_shift--;
    }
    m_used = 0;
    if (m_in_batch)
    {
        remap.assign(old_slots.size(), 0);
    }
    for (std::size_t j = 0; j < old_slots.size(); j++)
    {
        const Slot& s = old_slots[j];
        if (s.key == EMPTY_KEY)
        {
            continue;
        }
        std::size_t i = slotIndexFor(s.key);
        while (m_slots[i].key != EMPTY_KEY)
        {
            i = (i + 1) & m_mask;
        }
        m_slots[i] = s;
        m_used++;
        if (m_in_batch)
        {
            remap[j] = i;
            m_stamps[i] = old_stamps[j];  // stamps travel with the slots
        }                                 // else: stamps restart at 0 with the epoch below
    }
    if (m_in_batch)
    {
        for (std::size_t k = 0; k < m_touched_count; k++)
        {
            Touched& t = m_touched[k];
            t.slot = remap[t.slot];
        }
    }
    else
    {
        m_epoch = 0;
    }
}

inline std::size_t WeightedHistogram::probeOrInsert(
    Slot* slots, std::size_t mask, unsigned shift, std::uint64_t key, std::size_t& used)
{
    std::size_t j = hashSlot(key, shift);
    while (slots[j].key != key)
    {
        if (slots[j].key == EMPTY_KEY)
        {
            slots[j].key = key;
            slots[j].w = 0;
            used++;
            break;
        }
        j = (j + 1) & mask;
    }
    return j;
}

std::size_t WeightedHistogram::findOrInsert(std::uint64_t key)
{
    return probeOrInsert(m_slots.data(), m_mask, m_shift, key, m_used);
}

inline void WeightedHistogram::accountChange(Slot& s, double old_w)
{
    // wLogW(old_w) is the value added to S when the cell got old_w (same
    // function of the same weight), so S matches recomputing it.
    m_sum_wlogw += wLogW(s.w) - wLogW(old_w);
    m_occupied = m_occupied + (s.w > 0 ? 1 : 0) - (old_w > 0 ? 1 : 0);
}

void WeightedHistogram::add(std::uint64_t key, double w)
{
    ASSERTMSG_(!m_in_batch, "WeightedHistogram::add() inside a batch: use addDeferred()");
    if (2 * (m_used + 1) > m_slots.size())
    {
        rehash(2 * m_slots.size());
    }
    const std::size_t i = findOrInsert(key);
    logSlot(i);
    Slot& s = m_slots[i];
    const double old_w = s.w;
    s.w = cleanResidue(old_w + w, old_w, w);
    m_total += w;
    accountChange(s, old_w);
}

void WeightedHistogram::beginBatch(std::size_t max_new_cells)
{
    ASSERTMSG_(!m_in_batch, "WeightedHistogram::beginBatch() twice");
    if (2 * (m_used + max_new_cells) > m_slots.size())
    {
        rehash(nextPow2(2 * (m_used + max_new_cells)));
    }
    if (m_touched.size() < max_new_cells)
    {
        m_touched.resize(max_new_cells);
    }
    m_epoch++;
    if (m_epoch == 0)
    {  // wrapped: reset every stamp once every 2^32 batches
        std::fill(m_stamps.begin(), m_stamps.end(), 0u);
        m_epoch = 1;
    }
    m_touched_count = 0;
    m_in_batch = true;
}

void WeightedHistogram::addDeferred(std::uint64_t key, double w)
{
    if (2 * (m_used + 1) > m_slots.size())
    {
        rehash(2 * m_slots.size());  // keeps the batch's stamps and Touched slots valid
    }
    if (m_touched_count == m_touched.size())
    {
        m_touched.resize(2 * m_touched.size() + 64);
    }
    const std::size_t i = findOrInsert(key);
    Slot& s = m_slots[i];
    // Branch-free first-touch record: always written, kept only on first touch
    // (whether a cell was touched before is unpredictable).
    m_touched[m_touched_count] = {i, s.w};
    m_touched_count += (m_stamps[i] != m_epoch) ? 1 : 0;
    m_stamps[i] = m_epoch;
    s.w += w;  // rounding residue is cleaned once per cell in endBatch()
    m_total += w;
}

void WeightedHistogram::addDeferredMany(const Update* updates, std::size_t n)
{
    constexpr std::size_t AHEAD = 12;
    if (m_touched.size() < m_touched_count + n)
    {
        m_touched.resize(m_touched_count + n);
    }
    // Until the table must grow, table and counters live in locals. Through
    // the members (which slot stores may alias) the touched count and W
    // formed loop-carried store-forwarding chains. Same operations, same order.
    const std::size_t capacity = m_slots.size();
    Slot* const slots = m_slots.data();
    std::uint32_t* const stamps = m_stamps.data();
    Touched* const touched = m_touched.data();
    const std::size_t mask = m_mask;
    const unsigned shift = m_shift;
    const std::uint32_t epoch = m_epoch;
    std::size_t count = m_touched_count;
    std::size_t used = m_used;
    double total = m_total;
    std::size_t i = 0;
    for (; i < n && 2 * (used + 1) <= capacity; i++)
    {
        if (i + AHEAD < n)
        {
            __builtin_prefetch(&slots[hashSlot(updates[i + AHEAD].key, shift)], 1);
        }
        const std::uint64_t key = updates[i].key;
        const std::size_t j = probeOrInsert(slots, mask, shift, key, used);
        Slot& sl = slots[j];
        touched[count] = {j, sl.w};
        count += (stamps[j] != epoch) ? 1 : 0;
        stamps[j] = epoch;
        sl.w += updates[i].w;
        total += updates[i].w;
    }
    m_touched_count = count;
    m_used = used;
    m_total = total;
    for (; i < n; i++)
    {  // the table may grow: the general per-update form
        addDeferred(updates[i].key, updates[i].w);
    }
}

template <bool kIntegral>
void WeightedHistogram::addManyImpl(const Update* updates, std::size_t n)
{
    ASSERTMSG_(!m_in_batch, "WeightedHistogram::addMany() inside a batch");
    constexpr std::size_t AHEAD = 32;
    // Until the table must grow, sums in locals (see addDeferredMany()); the
    // same operations in the same order as add(), so S and W are bit-identical.
    // Integer weights sum exactly: no residue clean-up, integer w log w.
    const std::size_t capacity = m_slots.size();
    Slot* const slots = m_slots.data();
    const std::size_t mask = m_mask;
    const unsigned shift = m_shift;
    std::size_t used = m_used;
    std::size_t occupied = m_occupied;
    double total = m_total;
    double sum = m_sum_wlogw;
    // The table pointer in a register: through the global, every look-up
    // was two more dependent loads (the GOT, then the pointer).
    const double* const table = s_wlogw_table;
    const bool record = m_undo_valid;
    UndoRecord* const log_begin = record ? reserveUndo(n) : nullptr;
    UndoRecord* log = log_begin;
    std::size_t i = 0;
    for (; i < n && 2 * (used + 1) <= capacity; i++)
    {
        if (i + AHEAD < n)
        {
            __builtin_prefetch(&slots[hashSlot(updates[i + AHEAD].key, shift)], 1);
        }
        const double w = updates[i].w;
        const std::size_t j = probeOrInsert(slots, mask, shift, updates[i].key, used);
        Slot& sl = slots[j];
        const double old_w = sl.w;
        if (record)
        {
            log->slot = j;
            log->w = old_w;
            ++log;
        }
        if constexpr (kIntegral)
        {
            sl.w = old_w + w;
            sum += integralWLogW(sl.w, table) - integralWLogW(old_w, table);
        }
        else
        {
            sl.w = cleanResidue(old_w + w, old_w, w);
            sum += wLogW(sl.w) - wLogW(old_w);
        }
        total += w;
        occupied = occupied + (sl.w > 0 ? 1 : 0) - (old_w > 0 ? 1 : 0);
    }
    m_used = used;
    m_occupied = occupied;
    m_total = total;
    m_sum_wlogw = sum;
    m_undo_count += static_cast<std::size_t>(log - log_begin);
    for (; i < n; i++)
    {  // the table may grow: the general per-update form
        add(updates[i].key, updates[i].w);
    }
}

void WeightedHistogram::addMany(const Update* updates, std::size_t n)
{
    addManyImpl<false>(updates, n);
}

void WeightedHistogram::addManyIntegral(const Update* updates, std::size_t n)
{
    addManyImpl<true>(updates, n);
}

void WeightedHistogram::accumulateMany(const Update* updates, std::size_t n)
{
    ASSERTMSG_(!m_in_batch, "WeightedHistogram::accumulateMany() inside a batch");
    cancelUndoRecord();
    constexpr std::size_t AHEAD = 12;
    std::size_t i = 0;
    while (i < n)
    {
        // Until the table must grow, table and sums in locals (see
        // addDeferredMany()); then grow and go on.
        const std::size_t capacity = m_slots.size();
        Slot* const slots = m_slots.data();
        const std::size_t mask = m_mask;
        const unsigned shift = m_shift;
        std::size_t used = m_used;
        double total = m_total;
        for (; i < n && 2 * (used + 1) <= capacity; i++)
        {
            if (i + AHEAD < n)
            {
                __builtin_prefetch(&slots[hashSlot(updates[i + AHEAD].key, shift)], 1);
            }
            slots[probeOrInsert(slots, mask, shift, updates[i].key, used)].w += updates[i].w;
            total += updates[i].w;
        }
        m_used = used;
        m_total = total;
        if (i < n)
        {
            rehash(2 * m_slots.size());
        }
    }
}

std::size_t WeightedHistogram::recomputeSums(Update* cells_out)
{
    ASSERTMSG_(!m_in_batch, "WeightedHistogram::recomputeSums() inside a batch");
    cancelUndoRecord();
    double sum = 0;
    std::size_t occupied = 0;
    for (auto& sl : m_slots)
    {
        if (sl.key != EMPTY_KEY)
        {
            sum += wLogW(sl.w);
            if (cells_out && sl.w > 0)
            {
                cells_out[occupied] = {sl.key, sl.w};
            }
            occupied += sl.w > 0 ? 1 : 0;
        }
    }
    m_sum_wlogw = sum;
    m_occupied = occupied;
    return occupied;
}

void WeightedHistogram::endBatch()
{
    ASSERTMSG_(m_in_batch, "WeightedHistogram::endBatch() without beginBatch()");
    // Sums in locals, as in accountChange() (slot stores may alias members).
    Slot* const slots = m_slots.data();
    const Touched* const touched = m_touched.data();
    const std::size_t count = m_touched_count;
    double sum = m_sum_wlogw;
    std::size_t occupied = m_occupied;
    if (m_undo_valid)
    {  // the cells' states before the batch (the slot still holds the old w log w)
        UndoRecord* const log = reserveUndo(count);
        for (std::size_t k = 0; k < count; k++)
        {
            log[k] = {touched[k].slot, touched[k].old_w};
        }
        m_undo_count += count;
    }
    for (std::size_t k = 0; k < count; k++)
    {
        const Touched& t = touched[k];
        Slot& s = slots[t.slot];
        s.w = cleanResidue(s.w, t.old_w, s.w - t.old_w);
        if (s.w != t.old_w)
        {
            sum += wLogW(s.w) - wLogW(t.old_w);
            occupied = occupied + (s.w > 0 ? 1 : 0) - (t.old_w > 0 ? 1 : 0);
        }
    }
    m_sum_wlogw = sum;
    m_occupied = occupied;
    m_in_batch = false;
}

void WeightedHistogram::beginUndoRecord()
{
    ASSERTMSG_(!m_in_batch, "WeightedHistogram::beginUndoRecord() inside a batch");
    m_undo_count = 0;
    m_undo_valid = true;
    m_undo_total = m_total;
    m_undo_sum = m_sum_wlogw;
    m_undo_occupied = m_occupied;
}

void WeightedHistogram::rollback()
{
    ASSERTMSG_(!m_in_batch, "WeightedHistogram::rollback() inside a batch");
    ASSERTMSG_(m_undo_valid, "WeightedHistogram::rollback(): no valid undo record");
    // Newest first: a cell changed twice ends with its oldest state.
    Slot* const slots = m_slots.data();
    const UndoRecord* const log = m_undo_log.data();
    constexpr std::size_t AHEAD = 32;
    for (std::size_t k = m_undo_count; k-- > 0;)
    {
        if (k >= AHEAD)
        {  // the slots are scattered over a table larger than the L2 cache
            __builtin_prefetch(&slots[log[k - AHEAD].slot], 1);
        }
        const UndoRecord& r = log[k];
        slots[r.slot].w = r.w;
    }
    m_total = m_undo_total;
    m_sum_wlogw = m_undo_sum;
    m_occupied = m_undo_occupied;
    cancelUndoRecord();
}

void WeightedHistogram::dropUndoRecord()
{
    cancelUndoRecord();
}

double WeightedHistogram::weight(std::uint64_t key) const
{
    std::size_t i = slotIndexFor(key);
    for (;;)
    {
        const std::uint64_t k = m_slots[i].key;
        if (k == key)
        {
            return m_slots[i].w;
        }
        if (k == EMPTY_KEY)
        {
            return 0.0;
        }
        i = (i + 1) & m_mask;
    }
}

double WeightedHistogram::entropyFromScratch() const
{
    double total = 0;
    double sum = 0;
    forEachCell(
        [&](std::uint64_t, double w)
        {
            total += w;
            sum += w * std::log(w);
        });
    return entropyFrom(total, sum);
}

}  // namespace emslam::maps
