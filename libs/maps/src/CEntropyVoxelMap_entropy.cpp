// SPDX-License-Identifier: BSD-3-Clause
// CEntropyVoxelMap: binning, incremental moves, entropies, energy, likelihood.
#include <emslam/maps/CEntropyVoxelMap.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>

using emslam::CEntropyVoxelMap;
using emslam::maps::CellIndex;
using emslam::maps::EntropyTerm;
using emslam::maps::NUM_ENTROPY_TERMS;
using emslam::maps::packCellKey;
using emslam::maps::WeightedHistogram;
using emslam::maps::WeightedPointCloud;

namespace
{
/** floor() for values well inside the int32 range, without a libm call. */
inline std::int32_t fastFloor(double v)
{
    const auto i = static_cast<std::int32_t>(v);
    return i - static_cast<std::int32_t>(v < static_cast<double>(i));
}

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

/** Whether moves update term `t` through a deferred batch (see applyCellDelta()).
 * Measured on the benchmark: all-immediate is 7-20% slower for the marginals. */
inline bool deferInMoves(std::size_t t)
{
    return t != static_cast<std::size_t>(EntropyTerm::H3D);
}
/** Axes kept by each term (x, y, z), indexed by EntropyTerm. */
constexpr std::int32_t TERM_AXES[NUM_ENTROPY_TERMS][3] = {
    {1, 1, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

/** Indices of the terms set in a mask. */
struct TermList
{
    std::size_t idx[NUM_ENTROPY_TERMS]{};
    std::size_t n{0};
    explicit TermList(emslam::maps::TermMask m)
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
}  // namespace

void CEntropyVoxelMap::computeCells(
    const WeightedPointCloud& cloud,
    const mrpt::poses::CPose3D& pose,
    std::vector<CellIndex>& out) const
{
    const auto& R = pose.getRotationMatrix();
    const double inv = 1.0 / m_creation.cell_size;
    // Fold 1/l_d into the transform: cell = floor((R p + t) / l_d).
    const double r00 = R(0, 0) * inv, r01 = R(0, 1) * inv, r02 = R(0, 2) * inv;
    const double r10 = R(1, 0) * inv, r11 = R(1, 1) * inv, r12 = R(1, 2) * inv;
    const double r20 = R(2, 0) * inv, r21 = R(2, 1) * inv, r22 = R(2, 2) * inv;
    const double tx = pose.x() * inv, ty = pose.y() * inv, tz = pose.z() * inv;
    const std::size_t n = cloud.points.size();
    out.resize(n);
    const auto* p = cloud.points.data();
    CellIndex* c = out.data();
    for (std::size_t i = 0; i < n; i++)
    {
        const double x = p[i].x, y = p[i].y, z = p[i].z;
        c[i].x = fastFloor(r00 * x + r01 * y + r02 * z + tx);
        c[i].y = fastFloor(r10 * x + r11 * y + r12 * z + ty);
        c[i].z = fastFloor(r20 * x + r21 * y + r22 * z + tz);
    }
}

void CEntropyVoxelMap::beginBatches(std::size_t max_new_cells, bool include_3d)
{
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        if (include_3d || deferInMoves(terms.idx[k]))
        {
            m_hist[terms.idx[k]].beginBatch(max_new_cells);
        }
    }
}

void CEntropyVoxelMap::endBatches(bool include_3d)
{
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        if (include_3d || deferInMoves(terms.idx[k]))
        {
            m_hist[terms.idx[k]].endBatch();
        }
    }
}

void CEntropyVoxelMap::resetTracked()
{
    for (auto& h : m_hist)
    {
        h.clear();
    }
    m_total_weight = 0;
}

void CEntropyVoxelMap::addToTracked(const Observation& o, double sign)
{
    const TermList terms(m_tracked);
    const std::size_t n = o.cloud.size();
    beginBatches(n, true);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        const std::size_t t = terms.idx[k];
        WeightedHistogram& h = m_hist[t];
        for (std::size_t j = 0; j < n; j++)
        {
            h.addDeferred(termKey(t, o.cells[j]), sign * o.cloud.weights[j]);
        }
    }
    endBatches(true);
}

void CEntropyVoxelMap::applyCellDelta(
    const WeightedPointCloud& cloud,
    const std::vector<CellIndex>& from,
    const std::vector<CellIndex>& to)
{
    const TermList terms(m_tracked);
    const std::size_t n = cloud.size();
    // Pack each point's from/to 3D cell once; a term's key is then the 3D
    // key with the dropped axes' fields replaced by the packed 0 (same bits
    // as packCellKey() with those axes set to 0).
    m_keys3d.resize(2 * n);
    std::uint64_t* const kf = m_keys3d.data();
    std::uint64_t* const kt = kf + n;
    for (std::size_t j = 0; j < n; j++)
    {
        kf[j] = packCellKey(from[j].x, from[j].y, from[j].z);
        kt[j] = packCellKey(to[j].x, to[j].y, to[j].z);
    }
    const std::uint64_t zero_key = packCellKey(0, 0, 0);
    // One pass per term: collect the (cell, ±w) updates of the points whose
    // projected cell changes, then hand them to the histogram in bulk.
    for (std::size_t k = 0; k < terms.n; k++)
    {
        const std::size_t t = terms.idx[k];
        constexpr std::uint64_t FIELD = (std::uint64_t{1} << 21) - 1;
        const std::uint64_t keep =  // all-ones fields for the kept axes
            (TERM_AXES[t][0] ? FIELD << 42 : 0) | (TERM_AXES[t][1] ? FIELD << 21 : 0) |
            (TERM_AXES[t][2] ? FIELD : 0);
        const std::uint64_t fill = zero_key & ~keep;
        // Branch-free collection: both updates are always written and kept
        // only if the projected cell changes (a data-dependent branch here
        // mispredicts about half of the time).
        if (m_updates.size() < 2 * n)
        {  // grow only: shrinking and regrowing value-initialised it every time
            m_updates.resize(2 * n);
        }
        WeightedHistogram::Update* u = m_updates.data();
        const float* const wts = cloud.weights.data();
        std::size_t count = 0;
        for (std::size_t j = 0; j < n; j++)
        {
            const std::uint64_t ka = (kf[j] & keep) | fill;
            const std::uint64_t kb = (kt[j] & keep) | fill;
            const double w = wts[j];
            u[count].key = ka;
            u[count].w = -w;
            u[count + 1].key = kb;
            u[count + 1].w = w;
            count += (ka != kb) ? 2 : 0;
        }
        if (!deferInMoves(t))
        {
            // 3D cells are mostly touched once and hold small integer
            // weights: immediate updates (table look-ups) beat deferral.
            m_hist[t].addMany(u, count);
        }
        else
        {
            // Marginal cells collect many updates with large weights:
            // deferral evaluates w log w once per touched cell.
            m_hist[t].addDeferredMany(u, count);
        }
    }
}

double CEntropyVoxelMap::moveObservation(std::size_t i, const mrpt::poses::CPose3D& T_world_obs)
{
    return moveObservations({ObservationMove{i, T_world_obs}});
}

double CEntropyVoxelMap::moveObservations(const std::vector<ObservationMove>& moves)
{
    std::size_t max_new = 0;
    for (const auto& mv : moves)
    {
        if (mv.index >= m_obs.size())
        {
            THROW_EXCEPTION_FMT(
                "CEntropyVoxelMap::moveObservations(): observation index %zu out of range "
                "(%zu observations)",
                mv.index, m_obs.size());
        }
        max_new += m_obs[mv.index].cloud.size();
    }
    if (m_undo.size() < moves.size())
    {
        m_undo.resize(moves.size());
    }
    m_undo_count = 0;
    beginBatches(max_new, false);
    for (std::size_t k = 0; k < moves.size(); k++)
    {
        Observation& o = m_obs[moves[k].index];
        UndoEntry& e = m_undo[k];
        e.index = moves[k].index;
        e.old_pose = o.pose;
        computeCells(o.cloud, moves[k].pose, e.cells);
        applyCellDelta(o.cloud, o.cells, e.cells);
        std::swap(o.cells, e.cells);  // e.cells now keeps the old cells
        o.pose = moves[k].pose;
    }
    endBatches(false);
    m_undo_count = moves.size();
    return energy();
}

double CEntropyVoxelMap::revertLastMove()
{
    ASSERTMSG_(m_undo_count > 0, "CEntropyVoxelMap::revertLastMove(): nothing to revert");
    std::size_t max_new = 0;
    for (std::size_t k = 0; k < m_undo_count; k++)
    {
        max_new += m_obs[m_undo[k].index].cloud.size();
    }
    beginBatches(max_new, false);
    for (std::size_t k = m_undo_count; k-- > 0;)
    {
        UndoEntry& e = m_undo[k];
        Observation& o = m_obs[e.index];
        applyCellDelta(o.cloud, o.cells, e.cells);
        std::swap(o.cells, e.cells);
        o.pose = e.old_pose;
    }
    endBatches(false);
    m_undo_count = 0;
    return energy();
}

double CEntropyVoxelMap::energy() const
{
    double e = 0;
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        e += m_hist[terms.idx[k]].entropy();
    }
    return e;
}

const WeightedHistogram* CEntropyVoxelMap::trackedHistogram(EntropyTerm t) const
{
    const auto i = static_cast<std::size_t>(t);
    return (m_tracked & (1u << i)) ? &m_hist[i] : nullptr;
}

WeightedHistogram CEntropyVoxelMap::buildHistogram(EntropyTerm t) const
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

double CEntropyVoxelMap::entropy(EntropyTerm t) const
{
    if (const auto* h = trackedHistogram(t))
    {
        return h->entropy();
    }
    return buildHistogram(t).entropy();
}

emslam::maps::EntropyTerms CEntropyVoxelMap::entropies() const
{
    emslam::maps::EntropyTerms out{};
    for (std::size_t t = 0; t < NUM_ENTROPY_TERMS; t++)
    {
        out[t] = entropy(static_cast<EntropyTerm>(t));
    }
    return out;
}

emslam::maps::EntropyTerms CEntropyVoxelMap::computeEntropiesFromScratch() const
{
    // Independent of every incremental state: cells recomputed from the poses,
    // entropies summed directly with std::log.
    std::vector<std::vector<CellIndex>> cells(m_obs.size());
    for (std::size_t i = 0; i < m_obs.size(); i++)
    {
        computeCells(m_obs[i].cloud, m_obs[i].pose, cells[i]);
    }
    emslam::maps::EntropyTerms out{};
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

double CEntropyVoxelMap::recomputeFromScratch()
{
    m_undo_count = 0;
    resetTracked();
    std::size_t n = 0;
    for (auto& o : m_obs)
    {
        computeCells(o.cloud, o.pose, o.cells);
        n += o.cloud.size();
        m_total_weight += o.cloud.totalWeight();
    }
    const TermList terms(m_tracked);
    const bool has3d = (m_tracked & emslam::maps::termBit(EntropyTerm::H3D)) != 0;
    // 3D first (from the points), then the marginals from the occupied 3D
    // cells, which are fewer than the points when observations overlap.
    // Histograms are empty here: accumulate weights, then one w log w per
    // cell (recomputeSums()) instead of one per point.
    if (has3d)
    {
        WeightedHistogram& h3 = m_hist[static_cast<std::size_t>(EntropyTerm::H3D)];
        for (const auto& o : m_obs)
        {
            m_updates.resize(o.cloud.size());
            for (std::size_t j = 0; j < o.cloud.size(); j++)
            {
                const CellIndex& c = o.cells[j];
                m_updates[j] = {packCellKey(c.x, c.y, c.z), o.cloud.weights[j]};
            }
            h3.accumulateMany(m_updates.data(), m_updates.size());
        }
    }
    // Occupied 3D cells, compacted by the same sweep that sums w log w: the
    // marginals then read n_cells3d entries (L2) instead of sweeping the table.
    std::size_t n_cells3d = 0;
    if (has3d)
    {
        WeightedHistogram& h3 = m_hist[static_cast<std::size_t>(EntropyTerm::H3D)];
        m_updates.resize(2 * h3.usedSlots());  // [0, n): 3D cells, [n, 2n): projected
        n_cells3d = h3.recomputeSums(m_updates.data());
    }
    for (std::size_t k = 0; k < terms.n; k++)
    {
        const std::size_t t = terms.idx[k];
        if (t == static_cast<std::size_t>(EntropyTerm::H3D))
        {
            continue;
        }
        WeightedHistogram& h = m_hist[t];
        if (has3d)
        {
            // Field stores into a pre-sized buffer: push_back of an Update
            // built on the stack stalled on store forwarding.
            const std::int32_t ax = TERM_AXES[t][0], ay = TERM_AXES[t][1], az = TERM_AXES[t][2];
            const WeightedHistogram::Update* cells3d = m_updates.data();
            WeightedHistogram::Update* u = m_updates.data() + n_cells3d;
            for (std::size_t j = 0; j < n_cells3d; j++)
            {
                const CellIndex c = emslam::maps::unpackCellKey(cells3d[j].key);
                u[j].key = packCellKey(c.x * ax, c.y * ay, c.z * az);
                u[j].w = cells3d[j].w;
            }
            h.accumulateMany(u, n_cells3d);
            h.recomputeSums();
        }
        else
        {
            h.beginBatch(0);
            for (const auto& o : m_obs)
            {
                for (std::size_t j = 0; j < o.cloud.size(); j++)
                {
                    h.addDeferred(termKey(t, o.cells[j]), o.cloud.weights[j]);
                }
            }
            h.endBatch();
        }
    }
    return energy();
}

CEntropyVoxelMap::MemoryStats CEntropyVoxelMap::memoryStats() const
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

double CEntropyVoxelMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    WeightedPointCloud raw;
    if (!observationToCloud(obs, raw) || raw.empty())
    {
        return 0.0;
    }
    const WeightedPointCloud cloud = emslam::maps::simplifyCloud(raw, m_creation.cell_size);
    std::vector<CellIndex> cells;
    computeCells(cloud, takenFrom, cells);

    // General term: the 3D histogram for 6DOF energies, XZ for 3DOF ones.
    const EntropyTerm gt = m_creation.dof == 6 ? EntropyTerm::H3D : EntropyTerm::XZ;
    const auto t = static_cast<std::size_t>(gt);
    WeightedHistogram built;
    const WeightedHistogram* map_h = trackedHistogram(gt);
    if (!map_h)
    {
        built = buildHistogram(gt);
        map_h = &built;
    }
    WeightedHistogram obs_h(cloud.size());
    for (std::size_t j = 0; j < cloud.size(); j++)
    {
        obs_h.add(termKey(t, cells[j]), cloud.weights[j]);
    }
    // Code length C(X) = W_X·H(X) = W_X log W_X − S_X [nats].
    const auto code = [](double W, double S) { return W > 0 ? W * std::log(W) - S : 0.0; };
    const double Wa = map_h->totalWeight(), Sa = map_h->sumWLogW();
    const double Wo = obs_h.totalWeight(), So = obs_h.sumWLogW();
    double Su = Sa;
    obs_h.forEachCell(
        [&](std::uint64_t key, double wo)
        {
            const double wa = map_h->weight(key);
            Su += WeightedHistogram::wLogW(wa + wo) - WeightedHistogram::wLogW(wa);
        });
    // logL = C(A) + C(O) − C(A ∪ O) ≤ 0: minus the weighted Jensen-Shannon
    // divergence between map and observation, times W_A + W_O.
    return code(Wa, Sa) + code(Wo, So) - code(Wa + Wo, Su);
}
