// SPDX-License-Identifier: BSD-3-Clause
// IncrementalEntropyGrid: entropies, energy, rebuilding from scratch, memory.
#include "TermKeys.h"

#include <emslam/maps/IncrementalEntropyGrid.h>

#include <future>

namespace emslam::maps
{
using detail::TERM_AXES;
using detail::termKey;
using detail::TermList;

double IncrementalEntropyGrid::energy() const
{
    double e = 0;
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        e += m_hist[terms.idx[k]].entropy();
    }
    return e;
}

const WeightedHistogram* IncrementalEntropyGrid::trackedHistogram(EntropyTerm t) const
{
    const auto i = static_cast<std::size_t>(t);
    return (m_tracked & (1u << i)) ? &m_hist[i] : nullptr;
}

WeightedHistogram IncrementalEntropyGrid::buildHistogram(EntropyTerm t) const
{
    const auto ti = static_cast<std::size_t>(t);
    std::size_t n = 0;
    for (const auto& o : m_obs)
    {
        n += o.cloud.size();
    }
    WeightedHistogram h(n / 2 + 16);
    h.beginBatch(n);
    for (const auto& o : m_obs)
    {
        for (std::size_t j = 0; j < o.cloud.size(); j++)
        {
            h.addDeferred(termKey(ti, o.cells[j]), o.cloud.weights[j]);
        }
    }
    h.endBatch();
    return h;
}

double IncrementalEntropyGrid::entropy(EntropyTerm t) const
{
    if (const auto* h = trackedHistogram(t))
    {
        return h->entropy();
    }
    return buildHistogram(t).entropy();
}

EntropyTerms IncrementalEntropyGrid::entropies() const
{
    EntropyTerms out{};
    for (std::size_t t = 0; t < NUM_ENTROPY_TERMS; t++)
    {
        out[t] = entropy(static_cast<EntropyTerm>(t));
    }
    return out;
}

EntropyTerms IncrementalEntropyGrid::computeEntropiesFromScratch() const
{
    // Independent of every incremental state: cells recomputed from the poses,
    // entropies summed directly with std::log.
    std::vector<std::vector<CellIndex>> cells(m_obs.size());
    for (std::size_t i = 0; i < m_obs.size(); i++)
    {
        computeCells(m_obs[i].cloud, m_obs[i].pose, cells[i]);
    }
    EntropyTerms out{};
    for (std::size_t t = 0; t < NUM_ENTROPY_TERMS; t++)
    {
        WeightedHistogram h;
        for (std::size_t i = 0; i < m_obs.size(); i++)
        {
            for (std::size_t j = 0; j < cells[i].size(); j++)
            {
                h.add(termKey(t, cells[i][j]), m_obs[i].cloud.weights[j]);
            }
        }
        out[t] = h.entropyFromScratch();
    }
    return out;
}

double IncrementalEntropyGrid::recomputeFromScratch()
{
    commitMove();
    resetTracked();
    std::vector<const std::vector<CellIndex>*> cells(m_obs.size());
    for (std::size_t i = 0; i < m_obs.size(); i++)
    {
        Observation& o = m_obs[i];
        computeCells(o.cloud, o.pose, o.cells, &o.box);
        m_total_weight += o.weight_sum;
        m_integral_weights = m_integral_weights && o.integral_weights;
        cells[i] = &o.cells;
    }
    fillTracked(cells, m_hist, m_updates);
    return energy();
}

double IncrementalEntropyGrid::energyAtPoses(const std::vector<mrpt::poses::CPose3D>& poses) const
{
    if (poses.size() != m_obs.size())
    {
        THROW_EXCEPTION_FMT(
            "IncrementalEntropyGrid::energyAtPoses(): %zu poses for %zu observations", poses.size(),
            m_obs.size());
    }
    std::vector<std::vector<CellIndex>> cells(m_obs.size());
    const auto binned = [&](std::size_t first, std::size_t last)
    {
        for (std::size_t i = first; i < last; i++)
        {
            computeCells(m_obs[i].cloud, poses[i], cells[i]);
        }
    };
    std::size_t points = 0;
    for (const auto& o : m_obs)
    {
        points += o.cloud.size();
    }
    if (splitsWork(points))
    {
        const std::size_t half = m_obs.size() / 2;
        auto side = std::async(std::launch::async, binned, 0, half);
        binned(half, m_obs.size());
        side.get();
    }
    else
    {
        binned(0, m_obs.size());
    }
    std::vector<const std::vector<CellIndex>*> cell_lists(m_obs.size());
    for (std::size_t i = 0; i < m_obs.size(); i++)
    {
        cell_lists[i] = &cells[i];
    }
    std::array<WeightedHistogram, NUM_ENTROPY_TERMS> hist;
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        // About as many cells as at the current poses: no growth on the way.
        const std::size_t t = terms.idx[k];
        hist[t].reserve(m_hist[t].occupiedCells() + m_hist[t].occupiedCells() / 4);
    }
    std::vector<WeightedHistogram::Update> scratch;
    fillTracked(cell_lists, hist, scratch);
    double e = 0;
    for (std::size_t k = 0; k < terms.n; k++)
    {
        e += hist[terms.idx[k]].entropy();
    }
    return e;
}

void IncrementalEntropyGrid::fillTracked(
    const std::vector<const std::vector<CellIndex>*>& cells,
    std::array<WeightedHistogram, NUM_ENTROPY_TERMS>& hist,
    std::vector<WeightedHistogram::Update>& scratch) const
{
    const TermList terms(m_tracked);
    const bool has3d = (m_tracked & termBit(EntropyTerm::H3D)) != 0;
    // 3D first (from the points), then the marginals from the occupied 3D
    // cells, which are fewer than the points when observations overlap.
    // Histograms are empty here: accumulate weights, then one w log w per
    // cell (recomputeSums()) instead of one per point.
    std::size_t n_cells3d = 0;
    if (has3d)
    {
        WeightedHistogram& h3 = hist[static_cast<std::size_t>(EntropyTerm::H3D)];
        for (std::size_t i = 0; i < m_obs.size(); i++)
        {
            const WeightedPointCloud& cloud = m_obs[i].cloud;
            const std::vector<CellIndex>& c = *cells[i];
            scratch.resize(cloud.size());
            for (std::size_t j = 0; j < cloud.size(); j++)
            {
                scratch[j] = {packCellKey(c[j].x, c[j].y, c[j].z), cloud.weights[j]};
            }
            h3.accumulateMany(scratch.data(), scratch.size());
        }
        // Occupied 3D cells, compacted by the same sweep that sums w log w:
        // the marginals then read n_cells3d entries (L2) instead of sweeping
        // the table.
        scratch.resize(2 * h3.usedSlots());  // [0, n): 3D cells, [n, 2n): projected
        n_cells3d = h3.recomputeSums(scratch.data());
    }
    for (std::size_t k = 0; k < terms.n; k++)
    {
        const std::size_t t = terms.idx[k];
        if (t == static_cast<std::size_t>(EntropyTerm::H3D))
        {
            continue;
        }
        WeightedHistogram& h = hist[t];
        if (has3d)
        {
            // Field stores into a pre-sized buffer: push_back of an Update
            // built on the stack stalled on store forwarding.
            const std::int32_t ax = TERM_AXES[t][0], ay = TERM_AXES[t][1], az = TERM_AXES[t][2];
            const WeightedHistogram::Update* cells3d = scratch.data();
            WeightedHistogram::Update* u = scratch.data() + n_cells3d;
            for (std::size_t j = 0; j < n_cells3d; j++)
            {
                const CellIndex c = unpackCellKey(cells3d[j].key);
                u[j].key = packCellKey(c.x * ax, c.y * ay, c.z * az);
                u[j].w = cells3d[j].w;
            }
            h.accumulateMany(u, n_cells3d);
            h.recomputeSums();
        }
        else
        {
            h.beginBatch(0);
            for (std::size_t i = 0; i < m_obs.size(); i++)
            {
                const WeightedPointCloud& cloud = m_obs[i].cloud;
                const std::vector<CellIndex>& c = *cells[i];
                for (std::size_t j = 0; j < cloud.size(); j++)
                {
                    h.addDeferred(termKey(t, c[j]), cloud.weights[j]);
                }
            }
            h.endBatch();
        }
    }
}

IncrementalEntropyGrid::MemoryStats IncrementalEntropyGrid::memoryStats() const
{
    MemoryStats s;
    std::size_t occupied = 0;
    for (std::size_t t = 0; t < NUM_ENTROPY_TERMS; t++)
    {
        if (m_tracked & (1u << t))
        {
            s.histogram_bytes += m_hist[t].memoryBytes();
            occupied += m_hist[t].occupiedCells();
        }
    }
    if (const auto* h3 = trackedHistogram(EntropyTerm::H3D))
    {
        s.occupied_cells_3d = h3->occupiedCells();
    }
    for (const auto& o : m_obs)
    {
        s.observation_bytes += o.cloud.points.capacity() * sizeof(mrpt::math::TPoint3Df) +
                               o.cloud.weights.capacity() * sizeof(float) +
                               o.cells.capacity() * sizeof(CellIndex) + sizeof(Observation);
    }
    s.bytes_per_occupied_cell =
        occupied > 0 ? static_cast<double>(s.histogram_bytes) / static_cast<double>(occupied) : 0;
    return s;
}

}  // namespace emslam::maps
