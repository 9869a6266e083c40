// SPDX-License-Identifier: BSD-3-Clause
// IncrementalEntropyGrid: observations, binning, moves and their undo.
#include "TermKeys.h"

#include <emslam/maps/IncrementalEntropyGrid.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>
#include <future>
#include <utility>

namespace emslam::maps
{
using detail::termKey;
using detail::TermList;

namespace
{
/** Added to cell coordinates before truncating them (see biasedFloor()). */
constexpr double CELL_BIAS = 1 << 22;

/** floor(v − CELL_BIAS) for v = (coordinate / l_d) + CELL_BIAS: truncation of
 * a positive value, one conversion instead of a conversion, a compare and a
 * fix-up. Exact floor for cells within ±2^22 (the packed keys wrap at ±2^20
 * anyway), except that a coordinate within 2^-31 cells below a cell border
 * (the rounding of the biased sum) goes to the upper cell; every cell of
 * the map comes from here, so they are consistent. */
inline std::int32_t biasedFloor(double v)
{
    return static_cast<std::int32_t>(v) - static_cast<std::int32_t>(CELL_BIAS);
}

void requireCellSize(double cell_size)
{
    if (!(cell_size > 0) || !std::isfinite(cell_size))
    {
        THROW_EXCEPTION_FMT(
            "IncrementalEntropyGrid: invalid cell size %g (must be > 0 [m])", cell_size);
    }
}
}  // namespace

IncrementalEntropyGrid::IncrementalEntropyGrid(double cell_size, TermMask tracked)
{
    setGrid(cell_size, tracked);
}

void IncrementalEntropyGrid::setGrid(double cell_size, TermMask tracked)
{
    requireCellSize(cell_size);
    m_cell_size = cell_size;
    m_tracked = tracked;
    recomputeFromScratch();
}

void IncrementalEntropyGrid::assignObservations(
    double cell_size, TermMask tracked, std::vector<PosedCloud> observations)
{
    requireCellSize(cell_size);
    for (const auto& p : observations)
    {
        ASSERTMSG_(
            p.cloud.weights.size() == p.cloud.points.size(),
            "IncrementalEntropyGrid::assignObservations(): one weight per point is required");
    }
    m_obs.clear();
    m_obs.resize(observations.size());
    for (std::size_t i = 0; i < observations.size(); i++)
    {
        m_obs[i].cloud = std::move(observations[i].cloud);
        m_obs[i].pose = observations[i].pose;
        setWeightStats(m_obs[i]);
    }
    setGrid(cell_size, tracked);  // bins them
}

void IncrementalEntropyGrid::clear()
{
    m_obs.clear();
    commitMove();
    resetTracked();
}

std::size_t IncrementalEntropyGrid::addObservation(
    const WeightedPointCloud& cloud,
    const mrpt::poses::CPose3D& T_world_obs,
    bool already_simplified)
{
    ASSERTMSG_(
        cloud.weights.size() == cloud.points.size(),
        "IncrementalEntropyGrid::addObservation(): one weight per point is required");
    commitMove();
    Observation o;
    o.cloud = already_simplified ? cloud : simplifyCloud(cloud, m_cell_size);
    if (already_simplified)
    {
        sortByCell(o.cloud, m_cell_size);  // simplifyCloud() sorts already
    }
    o.pose = T_world_obs;
    computeCells(o.cloud, o.pose, o.cells, &o.box);
    addToTracked(o, +1.0);
    setWeightStats(o);
    m_total_weight += o.weight_sum;
    m_integral_weights = m_integral_weights && o.integral_weights;
    m_obs.push_back(std::move(o));
    return m_obs.size() - 1;
}

void IncrementalEntropyGrid::setWeightStats(Observation& o)
{
    o.weight_sum = o.cloud.totalWeight();
    o.integral_weights = o.cloud.hasIntegralWeights();
}

const mrpt::poses::CPose3D& IncrementalEntropyGrid::observationPose(std::size_t i) const
{
    ASSERTMSG_(i < m_obs.size(), "IncrementalEntropyGrid::observationPose(): index out of range");
    return m_obs[i].pose;
}

const WeightedPointCloud& IncrementalEntropyGrid::observationCloud(std::size_t i) const
{
    ASSERTMSG_(i < m_obs.size(), "IncrementalEntropyGrid::observationCloud(): index out of range");
    return m_obs[i].cloud;
}

void IncrementalEntropyGrid::computeCells(
    const WeightedPointCloud& cloud,
    const mrpt::poses::CPose3D& pose,
    std::vector<CellIndex>& out) const
{
    computeCells(cloud, pose, out, nullptr);
}

void IncrementalEntropyGrid::computeCells(
    const WeightedPointCloud& cloud,
    const mrpt::poses::CPose3D& pose,
    std::vector<CellIndex>& out,
    CellBox* box) const
{
    const auto& R = pose.getRotationMatrix();
    const double inv = 1.0 / m_cell_size;
    // Fold 1/l_d and CELL_BIAS into the transform: cell = floor((R p + t) / l_d).
    const double r00 = R(0, 0) * inv, r01 = R(0, 1) * inv, r02 = R(0, 2) * inv;
    const double r10 = R(1, 0) * inv, r11 = R(1, 1) * inv, r12 = R(1, 2) * inv;
    const double r20 = R(2, 0) * inv, r21 = R(2, 1) * inv, r22 = R(2, 2) * inv;
    const double tx = pose.x() * inv + CELL_BIAS, ty = pose.y() * inv + CELL_BIAS,
                 tz = pose.z() * inv + CELL_BIAS;
    const std::size_t n = cloud.points.size();
    out.resize(n);
    const auto* p = cloud.points.data();
    CellIndex* c = out.data();
    // Biased coordinates are positive, so truncation is floor. The bounding
    // box is tracked on them too (floor is monotonic): min/max of doubles
    // are single instructions.
    double lx = HUGE_VAL, ly = HUGE_VAL, lz = HUGE_VAL;
    double hx = -HUGE_VAL, hy = -HUGE_VAL, hz = -HUGE_VAL;
    for (std::size_t i = 0; i < n; i++)
    {
        const double x = p[i].x, y = p[i].y, z = p[i].z;
        const double bx = r00 * x + r01 * y + r02 * z + tx;
        const double by = r10 * x + r11 * y + r12 * z + ty;
        const double bz = r20 * x + r21 * y + r22 * z + tz;
        c[i].x = biasedFloor(bx);
        c[i].y = biasedFloor(by);
        c[i].z = biasedFloor(bz);
        lx = std::min(lx, bx);
        ly = std::min(ly, by);
        lz = std::min(lz, bz);
        hx = std::max(hx, bx);
        hy = std::max(hy, by);
        hz = std::max(hz, bz);
    }
    if (box)
    {
        *box =
            n > 0
                ? CellBox{{biasedFloor(lx), biasedFloor(ly), biasedFloor(lz)}, {biasedFloor(hx), biasedFloor(hy), biasedFloor(hz)}}
                : CellBox{};
    }
}

void IncrementalEntropyGrid::beginBatches(std::size_t max_new_cells)
{
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        m_hist[terms.idx[k]].beginBatch(max_new_cells);
    }
}

void IncrementalEntropyGrid::endBatches()
{
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        m_hist[terms.idx[k]].endBatch();
    }
}

void IncrementalEntropyGrid::resetTracked()
{
    for (auto& h : m_hist)
    {
        h.clear();
    }
    m_total_weight = 0;
    m_integral_weights = true;
}

void IncrementalEntropyGrid::addToTracked(const Observation& o, double sign)
{
    const TermList terms(m_tracked);
    const std::size_t n = o.cloud.size();
    beginBatches(n);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        const std::size_t t = terms.idx[k];
        WeightedHistogram& h = m_hist[t];
        for (std::size_t j = 0; j < n; j++)
        {
            h.addDeferred(termKey(t, o.cells[j]), sign * o.cloud.weights[j]);
        }
    }
    endBatches();
}

template <typename INDEX>
bool IncrementalEntropyGrid::distinctIndices(std::size_t count, INDEX&& index)
{
    m_seen.assign(m_obs.size(), 0);
    for (std::size_t k = 0; k < count; k++)
    {
        auto& seen = m_seen[index(k)];
        if (seen)
        {
            return false;
        }
        seen = 1;
    }
    return true;
}

double IncrementalEntropyGrid::moveObservation(
    std::size_t i, const mrpt::poses::CPose3D& T_world_obs)
{
    return moveObservations({ObservationMove{i, T_world_obs}});
}

double IncrementalEntropyGrid::moveObservations(const std::vector<ObservationMove>& moves)
{
    for (const auto& mv : moves)
    {
        if (mv.index >= m_obs.size())
        {
            THROW_EXCEPTION_FMT(
                "IncrementalEntropyGrid::moveObservations(): observation index %zu out of range "
                "(%zu observations)",
                mv.index, m_obs.size());
        }
    }
    if (m_undo.size() < moves.size())
    {
        m_undo.resize(moves.size());
    }
    m_undo_count = 0;
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        m_hist[terms.idx[k]].beginUndoRecord();
    }
    // Distinct observations: all new cells first, then every change at once
    // (see applyCellDeltas()). An observation moved twice: one move at a
    // time, each starting where the last ended.
    const bool together =
        distinctIndices(moves.size(), [&](std::size_t k) { return moves[k].index; });
    const auto finishMove = [&](std::size_t k)
    {
        Observation& o = m_obs[moves[k].index];
        UndoEntry& e = m_undo[k];
        std::swap(o.cells, e.cells);  // e.cells now keeps the old cells
        std::swap(o.box, e.box);
        o.pose = moves[k].pose;
    };
    const auto newCells = [&](std::size_t first, std::size_t last)
    {
        for (std::size_t k = first; k < last; k++)
        {
            computeCells(
                m_obs[moves[k].index].cloud, moves[k].pose, m_undo[k].cells, &m_undo[k].box);
        }
    };
    std::size_t points = 0;
    for (const auto& mv : moves)
    {
        points += m_obs[mv.index].cloud.size();
    }
    if (together && splitsWork(points))
    {
        // The observations' cells are independent: half of them on another thread.
        const std::size_t half = moves.size() / 2;
        auto side = std::async(std::launch::async, newCells, 0, half);
        newCells(half, moves.size());
        side.get();
    }
    else if (together)
    {
        newCells(0, moves.size());
    }
    m_changes.clear();
    for (std::size_t k = 0; k < moves.size(); k++)
    {
        Observation& o = m_obs[moves[k].index];
        UndoEntry& e = m_undo[k];
        e.index = moves[k].index;
        e.old_pose = o.pose;
        if (!together)
        {
            newCells(k, k + 1);
        }
        m_changes.push_back({&o.cloud, &o.cells, &e.cells, o.box, e.box});
        if (!together)
        {
            applyCellDeltas(&m_changes.back(), 1);
            finishMove(k);
        }
    }
    if (together)
    {
        applyCellDeltas(m_changes.data(), m_changes.size());
        for (std::size_t k = 0; k < moves.size(); k++)
        {
            finishMove(k);
        }
    }
    m_undo_count = moves.size();
    return energy();
}

double IncrementalEntropyGrid::revertLastMove()
{
    ASSERTMSG_(m_undo_count > 0, "IncrementalEntropyGrid::revertLastMove(): nothing to revert");
    // The histograms restore their own cells from their undo logs, unless
    // one of them grew meanwhile: then the cell changes are applied back.
    const TermList terms(m_tracked);
    bool rollback = true;
    for (std::size_t k = 0; k < terms.n; k++)
    {
        rollback = rollback && m_hist[terms.idx[k]].canRollback();
    }
    if (rollback)
    {
        const auto restore = [&](bool is3d)
        {
            for (std::size_t k = 0; k < terms.n; k++)
            {
                if ((terms.idx[k] == static_cast<std::size_t>(EntropyTerm::H3D)) == is3d)
                {
                    m_hist[terms.idx[k]].rollback();
                }
            }
        };
        std::size_t points = 0;
        for (std::size_t k = 0; k < m_undo_count; k++)
        {
            points += m_obs[m_undo[k].index].cloud.size();
        }
        if (splitsWork(points))
        {
            auto side = std::async(std::launch::async, restore, false);
            restore(true);
            side.get();
        }
        else
        {
            restore(true);
            restore(false);
        }
    }
    else
    {
        dropHistogramUndo();
    }
    const bool together =
        !rollback && distinctIndices(m_undo_count, [&](std::size_t k) { return m_undo[k].index; });
    if (together)
    {
        m_changes.clear();
        for (std::size_t k = 0; k < m_undo_count; k++)
        {
            const UndoEntry& e = m_undo[k];
            const Observation& o = m_obs[e.index];
            m_changes.push_back({&o.cloud, &o.cells, &e.cells, o.box, e.box});
        }
        applyCellDeltas(m_changes.data(), m_changes.size());
    }
    for (std::size_t k = m_undo_count; k-- > 0;)
    {
        UndoEntry& e = m_undo[k];
        Observation& o = m_obs[e.index];
        if (!rollback && !together)
        {
            const CellChange change{&o.cloud, &o.cells, &e.cells, o.box, e.box};
            applyCellDeltas(&change, 1);
        }
        std::swap(o.cells, e.cells);
        std::swap(o.box, e.box);
        o.pose = e.old_pose;
    }
    m_undo_count = 0;
    return energy();
}

void IncrementalEntropyGrid::setThreads(int threads)
{
    if (threads != 1 && threads != 2)
    {
        THROW_EXCEPTION_FMT(
            "IncrementalEntropyGrid::setThreads(): %d threads (must be 1 or 2)", threads);
    }
    m_threads = threads;
}

bool IncrementalEntropyGrid::splitsWork(std::size_t points) const
{
    // Only the 3D term beside marginal ones gives both threads a fair share;
    // measured: with the 3D term alone (Exp. 8) or the planar terms alone
    // (Exp. 11, 12), splitting the binning alone gains nothing or loses.
    const TermMask h3d = termBit(EntropyTerm::H3D);
    return m_threads >= 2 && points >= PARALLEL_MIN_POINTS && (m_tracked & h3d) != 0 &&
           (m_tracked & ~h3d) != 0;
}

void IncrementalEntropyGrid::commitMove()
{
    m_undo_count = 0;
    dropHistogramUndo();
}

void IncrementalEntropyGrid::dropHistogramUndo()
{
    for (auto& h : m_hist)
    {
        h.dropUndoRecord();
    }
}

}  // namespace emslam::maps
