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

/** Largest dense grid of applyMarginalDeltasDense() (8 B per cell). */
constexpr std::size_t DENSE_MAX_CELLS = std::size_t{1} << 16;
/** At most this many marginal terms (Exp. 8-12 track up to 3). */
constexpr std::size_t MAX_DENSE_TERMS = 3;

/** The dense grids of one applyMarginalDeltasDense() call. */
struct DenseGrids
{
    std::size_t n{0};
    std::size_t term[NUM_ENTROPY_TERMS]{};
    int a[MAX_DENSE_TERMS]{};  //!< grid index = d_a * stride + d_b (d: offset in the box)
    int b[MAX_DENSE_TERMS]{};  //!< a == b: 1D term, index d_b
    std::int32_t stride[MAX_DENSE_TERMS]{};
    std::size_t area[MAX_DENSE_TERMS]{};
    std::size_t offset[MAX_DENSE_TERMS]{};
};

/** Marginal term sets of the energies, each with a compiled scatter loop. */
enum class DensePattern
{
    None,
    XY_XZ_YZ,  //!< structured
    XZ_X_Z,    //!< planar_structured
    XZ,        //!< planar_low_structured
    Y          //!< low_structured
};

DensePattern termsPattern(const DenseGrids& g)
{
    const auto is = [&](std::size_t k, EntropyTerm t)
    { return g.term[k] == static_cast<std::size_t>(t); };
    if (g.n == 3 && is(0, EntropyTerm::XY) && is(1, EntropyTerm::XZ) && is(2, EntropyTerm::YZ))
    {
        return DensePattern::XY_XZ_YZ;
    }
    if (g.n == 3 && is(0, EntropyTerm::XZ) && is(1, EntropyTerm::X) && is(2, EntropyTerm::Z))
    {
        return DensePattern::XZ_X_Z;
    }
    if (g.n == 1 && is(0, EntropyTerm::XZ))
    {
        return DensePattern::XZ;
    }
    if (g.n == 1 && is(0, EntropyTerm::Y))
    {
        return DensePattern::Y;
    }
    return DensePattern::None;
}

/** Kept axes of one grid, as template arguments (A == B: 1D term). */
template <int A, int B>
struct GridAxes
{
    static constexpr int a = A;
    static constexpr int b = B;
};

struct ScatterArgs
{
    const CellIndex* from;
    const CellIndex* to;
    const float* weights;
    std::size_t n;
    std::int32_t lo[3];
    std::int32_t stride[MAX_DENSE_TERMS];
    double* const* grids;
};

/** Adds −w at each point's old grid cell and +w at its new one, for every
 * grid G... in one pass over the points (their offsets are computed once).
 * An unchanged cell adds ±0 (branch-free: the change is unpredictable). */
template <typename... G>
void scatterDeltas(const ScatterArgs& s)
{
    const std::int32_t lx = s.lo[0], ly = s.lo[1], lz = s.lo[2];
    const auto one = [&](std::size_t j)
    {
        const CellIndex& p = s.from[j];
        const CellIndex& q = s.to[j];
        const std::int32_t dp[3] = {p.x - lx, p.y - ly, p.z - lz};
        const std::int32_t dq[3] = {q.x - lx, q.y - ly, q.z - lz};
        const double w = s.weights[j];
        std::size_t k = 0;
        const auto grid = [&](auto axes)
        {
            using A = decltype(axes);
            std::int32_t ia = dp[A::b], ib = dq[A::b];
            if constexpr (A::a != A::b)
            {
                ia += dp[A::a] * s.stride[k];
                ib += dq[A::a] * s.stride[k];
            }
            const double wk = ia != ib ? w : 0.0;
            s.grids[k][ia] -= wk;
            s.grids[k][ib] += wk;
            k++;
        };
        (grid(G{}), ...);
    };
    // Points are stored in cell order, so consecutive points often hit the
    // same cell: their read-modify-writes would form one long dependency
    // chain through memory. Interleaving four distant quarters of the cloud
    // gives four independent chains.
    const std::size_t q = s.n / 4;
    for (std::size_t j = 0; j < q; j++)
    {
        one(j);
        one(j + q);
        one(j + 2 * q);
        one(j + 3 * q);
    }
    for (std::size_t j = 4 * q; j < s.n; j++)
    {
        one(j);
    }
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
    std::vector<CellIndex>& out,
    CellBox* box) const
{
    const auto& R = pose.getRotationMatrix();
    const double inv = 1.0 / m_creation.cell_size;
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

void CEntropyVoxelMap::beginBatches(std::size_t max_new_cells)
{
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        m_hist[terms.idx[k]].beginBatch(max_new_cells);
    }
}

void CEntropyVoxelMap::endBatches()
{
    const TermList terms(m_tracked);
    for (std::size_t k = 0; k < terms.n; k++)
    {
        m_hist[terms.idx[k]].endBatch();
    }
}

void CEntropyVoxelMap::resetTracked()
{
    for (auto& h : m_hist)
    {
        h.clear();
    }
    m_total_weight = 0;
    m_integral_weights = true;
}

void CEntropyVoxelMap::addToTracked(const Observation& o, double sign)
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

void CEntropyVoxelMap::addNetUpdates(
    std::size_t t, const WeightedHistogram::Update* u, std::size_t count)
{
    if (m_integral_weights)
    {
        m_hist[t].addManyIntegral(u, count);
    }
    else
    {
        m_hist[t].addMany(u, count);
    }
}

bool CEntropyVoxelMap::applyMarginalDeltasDense(
    const CellChange* changes, std::size_t count, const CellBox& box)
{
    const TermList terms(m_tracked);
    DenseGrids g;
    for (std::size_t k = 0; k < terms.n; k++)
    {
        const std::size_t t = terms.idx[k];
        if (t != static_cast<std::size_t>(EntropyTerm::H3D))
        {
            g.term[g.n++] = t;
        }
    }
    const auto pattern = termsPattern(g);
    if (pattern == DensePattern::None)
    {
        return false;
    }
    std::size_t n = 0;
    for (std::size_t c = 0; c < count; c++)
    {
        n += changes[c].cloud->size();
    }
    std::size_t dim[3];
    for (int a = 0; a < 3; a++)
    {
        dim[a] = static_cast<std::size_t>(std::int64_t{box.hi[a]} - box.lo[a] + 1);
    }
    // Grid k: row major over its kept axes (a, b), or over b alone for a 1D term.
    std::size_t total = 0;
    for (std::size_t k = 0; k < g.n; k++)
    {
        const auto& ax = TERM_AXES[g.term[k]];
        const int b = ax[2] ? 2 : (ax[1] ? 1 : 0);
        const int a = (ax[0] && b != 0) ? 0 : ((ax[1] && b == 2) ? 1 : b);
        g.a[k] = a;
        g.b[k] = b;
        g.stride[k] = a == b ? 0 : static_cast<std::int32_t>(dim[b]);
        g.area[k] = a == b ? dim[b] : dim[a] * dim[b];
        g.offset[k] = total;
        total += g.area[k];
        // The sweep costs ~area, the hash path a few times that per point.
        if (g.area[k] > DENSE_MAX_CELLS || g.area[k] > 16 * n + 4096)
        {
            return false;
        }
    }
    if (m_dense.size() < total)
    {
        m_dense.resize(total, 0.0);  // grows only; the sweep leaves it zero
    }
    double* grids[MAX_DENSE_TERMS]{};
    for (std::size_t k = 0; k < g.n; k++)
    {
        grids[k] = m_dense.data() + g.offset[k];
    }
    for (std::size_t c = 0; c < count; c++)
    {
        const ScatterArgs args{
            changes[c].from->data(),
            changes[c].to->data(),
            changes[c].cloud->weights.data(),
            changes[c].cloud->size(),
            {box.lo[0], box.lo[1], box.lo[2]},
            {g.stride[0], g.stride[1], g.stride[2]},
            grids};
        switch (pattern)
        {
            case DensePattern::XY_XZ_YZ:
                scatterDeltas<GridAxes<0, 1>, GridAxes<0, 2>, GridAxes<1, 2>>(args);
                break;
            case DensePattern::XZ_X_Z:
                scatterDeltas<GridAxes<0, 2>, GridAxes<0, 0>, GridAxes<2, 2>>(args);
                break;
            case DensePattern::XZ:
                scatterDeltas<GridAxes<0, 2>>(args);
                break;
            case DensePattern::Y:
                scatterDeltas<GridAxes<1, 1>>(args);
                break;
            case DensePattern::None:
                break;
        }
    }

    // Packed key fields of each box coordinate, per axis.
    m_fields.resize(dim[0] + dim[1] + dim[2]);
    std::uint64_t* field[3] = {
        m_fields.data(), m_fields.data() + dim[0], m_fields.data() + dim[0] + dim[1]};
    constexpr std::uint64_t FIELD = (std::uint64_t{1} << 21) - 1;
    for (int a = 0; a < 3; a++)
    {
        const std::uint64_t mask = FIELD << (42 - 21 * a);
        for (std::size_t i = 0; i < dim[a]; i++)
        {
            std::int32_t c[3] = {0, 0, 0};
            c[a] = box.lo[a] + static_cast<std::int32_t>(i);
            field[a][i] = packCellKey(c[0], c[1], c[2]) & mask;
        }
    }
    const std::uint64_t zero_key = packCellKey(0, 0, 0);
    // Sweep each grid: one net update per changed cell (branch-free
    // compaction), clearing the grid for the next call. Net updates hit
    // distinct cells: immediate updates, one w log w each.
    for (std::size_t k = 0; k < g.n; k++)
    {
        const std::size_t t = g.term[k];
        const int a = g.a[k], b = g.b[k];
        const std::size_t rows = a == b ? 1 : dim[a];
        const std::uint64_t keep_a = a == b ? 0 : FIELD << (42 - 21 * a);
        const std::uint64_t keep_b = FIELD << (42 - 21 * b);
        const std::uint64_t fill = zero_key & ~(keep_a | keep_b);
        if (m_updates.size() < g.area[k])
        {
            m_updates.resize(g.area[k]);
        }
        WeightedHistogram::Update* const u = m_updates.data();
        const std::uint64_t* const fb = field[b];
        double* row = grids[k];
        std::size_t net = 0;
        for (std::size_t ia = 0; ia < rows; ia++, row += dim[b])
        {
            const std::uint64_t ka = (a == b ? 0 : field[a][ia]) | fill;
            for (std::size_t ib = 0; ib < dim[b]; ib++)
            {
                const double v = row[ib];
                u[net].key = ka | fb[ib];
                u[net].w = v;
                net += v != 0 ? 1 : 0;
                row[ib] = 0;
            }
        }
        addNetUpdates(t, u, net);
    }
    return true;
}

void CEntropyVoxelMap::flushPending3d()
{
    if (m_pending3d_count > 0)
    {
        // 3D cells are mostly touched once and hold small integer weights:
        // immediate updates (table look-ups) beat deferral. All moved
        // observations at once: one call, one prefetching loop.
        addNetUpdates(
            static_cast<std::size_t>(EntropyTerm::H3D), m_pending3d.data(), m_pending3d_count);
        m_pending3d_count = 0;
    }
}

void CEntropyVoxelMap::applyCellDeltas(const CellChange* changes, std::size_t count)
{
    // Marginal cells are shared by many observations: when one set of dense
    // grids covers every change, the net change of each cell is taken over
    // all of them (one sweep, and the updates of overlapping observations
    // cancel before reaching the histogram).
    CellBox box;
    std::size_t points = 0;
    for (std::size_t c = 0; c < count; c++)
    {
        if (changes[c].cloud->size() == 0)
        {
            continue;  // its boxes are empty
        }
        const CellBox b = unionOf(changes[c].from_box, changes[c].to_box);
        box = points == 0 ? b : unionOf(box, b);
        points += changes[c].cloud->size();
    }
    const bool marginals_done = points > 0 && applyMarginalDeltasDense(changes, count, box);
    for (std::size_t c = 0; c < count; c++)
    {
        applyCellDelta(changes[c], marginals_done);
    }
    flushPending3d();
}

CEntropyVoxelMap::CellBox CEntropyVoxelMap::unionOf(const CellBox& a, const CellBox& b)
{
    CellBox u;
    for (int k = 0; k < 3; k++)
    {
        u.lo[k] = std::min(a.lo[k], b.lo[k]);
        u.hi[k] = std::max(a.hi[k], b.hi[k]);
    }
    return u;
}

void CEntropyVoxelMap::applyCellDelta(const CellChange& change, bool marginals_applied)
{
    const TermList terms(m_tracked);
    const WeightedPointCloud& cloud = *change.cloud;
    const std::vector<CellIndex>& from = *change.from;
    const std::vector<CellIndex>& to = *change.to;
    const std::size_t n = cloud.size();
    if (n == 0)
    {
        return;
    }
    // Pack each point's from/to 3D cell once (lazily: only the 3D term and
    // the hash path of large marginals use them); a term's key is then the
    // 3D key with the dropped axes' fields replaced by the packed 0 (same
    // bits as packCellKey() with those axes set to 0).
    bool packed = false;
    std::uint64_t* kf = nullptr;
    std::uint64_t* kt = nullptr;
    const auto pack = [&]()
    {
        m_keys3d.resize(2 * n);
        kf = m_keys3d.data();
        kt = kf + n;
        for (std::size_t j = 0; j < n; j++)
        {
            kf[j] = packCellKey(from[j].x, from[j].y, from[j].z);
            kt[j] = packCellKey(to[j].x, to[j].y, to[j].z);
        }
        packed = true;
    };
    const std::uint64_t zero_key = packCellKey(0, 0, 0);
    // Marginal cells collect many updates each: accumulate the net change
    // per cell in dense grids over the observation's box (no hashing per
    // update), then touch each changed cell once.
    const bool marginals_done =
        marginals_applied ||
        applyMarginalDeltasDense(&change, 1, unionOf(change.from_box, change.to_box));
    for (std::size_t k = 0; k < terms.n; k++)
    {
        const std::size_t t = terms.idx[k];
        const bool is3d = t == static_cast<std::size_t>(EntropyTerm::H3D);
        if (!is3d && marginals_done)
        {
            continue;
        }
        if (!packed)
        {
            pack();
        }
        // Hash path: collect the (cell, ±w) updates of the points whose
        // projected cell changes, then hand them to the histogram in bulk.
        constexpr std::uint64_t FIELD = (std::uint64_t{1} << 21) - 1;
        const std::uint64_t keep =  // all-ones fields for the kept axes
            (TERM_AXES[t][0] ? FIELD << 42 : 0) | (TERM_AXES[t][1] ? FIELD << 21 : 0) |
            (TERM_AXES[t][2] ? FIELD : 0);
        const std::uint64_t fill = zero_key & ~keep;
        // Branch-free collection: both updates are always written and kept
        // only if the projected cell changes (a data-dependent branch here
        // mispredicts about half of the time). The 3D updates are only
        // collected: flushPending3d() applies those of every moved
        // observation together.
        std::vector<WeightedHistogram::Update>& buffer = is3d ? m_pending3d : m_updates;
        const std::size_t base = is3d ? m_pending3d_count : 0;
        if (buffer.size() < base + 2 * n)
        {  // grow only: shrinking and regrowing value-initialised it every time
            buffer.resize(std::max(base + 2 * n, 2 * buffer.size()));
        }
        WeightedHistogram::Update* u = buffer.data() + base;
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
        if (is3d)
        {
            m_pending3d_count += count;
        }
        else
        {
            // Marginal cells collect many updates with large weights:
            // deferral evaluates w log w once per touched cell.
            m_hist[t].beginBatch(count);
            m_hist[t].addDeferredMany(u, count);
            m_hist[t].endBatch();
        }
    }
}

double CEntropyVoxelMap::moveObservation(std::size_t i, const mrpt::poses::CPose3D& T_world_obs)
{
    return moveObservations({ObservationMove{i, T_world_obs}});
}

double CEntropyVoxelMap::moveObservations(const std::vector<ObservationMove>& moves)
{
    for (const auto& mv : moves)
    {
        if (mv.index >= m_obs.size())
        {
            THROW_EXCEPTION_FMT(
                "CEntropyVoxelMap::moveObservations(): observation index %zu out of range "
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
    m_changes.clear();
    for (std::size_t k = 0; k < moves.size(); k++)
    {
        Observation& o = m_obs[moves[k].index];
        UndoEntry& e = m_undo[k];
        e.index = moves[k].index;
        e.old_pose = o.pose;
        computeCells(o.cloud, moves[k].pose, e.cells, &e.box);
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

double CEntropyVoxelMap::revertLastMove()
{
    ASSERTMSG_(m_undo_count > 0, "CEntropyVoxelMap::revertLastMove(): nothing to revert");
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
        for (std::size_t k = 0; k < terms.n; k++)
        {
            m_hist[terms.idx[k]].rollback();
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

void CEntropyVoxelMap::commitMove()
{
    m_undo_count = 0;
    dropHistogramUndo();
}

void CEntropyVoxelMap::dropHistogramUndo()
{
    for (auto& h : m_hist)
    {
        h.dropUndoRecord();
    }
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
    commitMove();
    resetTracked();
    for (auto& o : m_obs)
    {
        computeCells(o.cloud, o.pose, o.cells, &o.box);
        m_total_weight += o.weight_sum;
        m_integral_weights = m_integral_weights && o.integral_weights;
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
