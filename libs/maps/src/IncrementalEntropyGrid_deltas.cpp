// SPDX-License-Identifier: BSD-3-Clause
// IncrementalEntropyGrid: applying the cell changes of moved observations to
// the tracked histograms (dense marginal grids, hashed bulk updates).
#include "TermKeys.h"

#include <emslam/maps/IncrementalEntropyGrid.h>

#include <algorithm>
#include <future>

namespace emslam::maps
{
using detail::TERM_AXES;
using detail::TermList;

namespace
{
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

/** The dense grids of the tracked marginal terms (every term but H3D), in
 * the order they are tracked; their layout is set by layOutGrids(). */
DenseGrids marginalGrids(const TermList& terms)
{
    DenseGrids g;
    for (std::size_t k = 0; k < terms.n; k++)
    {
        const std::size_t t = terms.idx[k];
        if (t != static_cast<std::size_t>(EntropyTerm::H3D))
        {
            g.term[g.n++] = t;
        }
    }
    return g;
}

/** Grid k: row major over its kept axes (a, b), or over b alone for a 1D
 * term, over a box of `dim` cells; the grids follow each other in one
 * buffer of `total` cells. False: a grid is too large for the dense path
 * with `n` moved points. */
bool layOutGrids(DenseGrids& g, const std::size_t dim[3], std::size_t n, std::size_t& total)
{
    total = 0;
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
    return true;
}

/** scatterDeltas() with the grids of `pattern`. */
void scatterPattern(DensePattern pattern, const ScatterArgs& args)
{
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

/** One packed cell-key field per bit range of a key (21 bits per axis). */
constexpr std::uint64_t KEY_FIELD = (std::uint64_t{1} << 21) - 1;

/** The packed key fields of each box coordinate, per axis: field[a][i] is
 * axis a's bits of the key of coordinate lo[a] + i. */
void fillKeyFields(
    const std::int32_t lo[3], const std::size_t dim[3], std::uint64_t* const field[3])
{
    for (int a = 0; a < 3; a++)
    {
        const std::uint64_t mask = KEY_FIELD << (42 - 21 * a);
        for (std::size_t i = 0; i < dim[a]; i++)
        {
            std::int32_t c[3] = {0, 0, 0};
            c[a] = lo[a] + static_cast<std::int32_t>(i);
            field[a][i] = packCellKey(c[0], c[1], c[2]) & mask;
        }
    }
}

/** Sweeps grid k: one net update per changed cell into `u` (branch-free
 * compaction), clearing the grid for the next call; returns how many. */
std::size_t sweepGrid(
    const DenseGrids& g,
    std::size_t k,
    const std::size_t dim[3],
    const std::uint64_t* const field[3],
    double* row,
    WeightedHistogram::Update* const u)
{
    const int a = g.a[k], b = g.b[k];
    const std::size_t rows = a == b ? 1 : dim[a];
    const std::uint64_t keep_a = a == b ? 0 : KEY_FIELD << (42 - 21 * a);
    const std::uint64_t keep_b = KEY_FIELD << (42 - 21 * b);
    const std::uint64_t fill = packCellKey(0, 0, 0) & ~(keep_a | keep_b);
    const std::uint64_t* const fb = field[b];
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
    return net;
}
}  // namespace

void IncrementalEntropyGrid::addNetUpdates(
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

bool IncrementalEntropyGrid::applyMarginalDeltasDense(
    const CellChange* changes, std::size_t count, const CellBox& box)
{
    DenseGrids g = marginalGrids(TermList(m_tracked));
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
    std::size_t total = 0;
    if (!layOutGrids(g, dim, n, total))
    {
        return false;
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
        scatterPattern(
            pattern, {changes[c].from->data(),
                      changes[c].to->data(),
                      changes[c].cloud->weights.data(),
                      changes[c].cloud->size(),
                      {box.lo[0], box.lo[1], box.lo[2]},
                      {g.stride[0], g.stride[1], g.stride[2]},
                      grids});
    }

    m_fields.resize(dim[0] + dim[1] + dim[2]);
    std::uint64_t* const field[3] = {
        m_fields.data(), m_fields.data() + dim[0], m_fields.data() + dim[0] + dim[1]};
    fillKeyFields(box.lo, dim, field);
    // Net updates hit distinct cells: immediate updates, one w log w each.
    for (std::size_t k = 0; k < g.n; k++)
    {
        if (m_updates.size() < g.area[k])
        {
            m_updates.resize(g.area[k]);
        }
        const std::size_t net = sweepGrid(g, k, dim, field, grids[k], m_updates.data());
        addNetUpdates(g.term[k], m_updates.data(), net);
    }
    return true;
}

void IncrementalEntropyGrid::applyCellDeltas(const CellChange* changes, std::size_t count)
{
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
    if (points == 0)
    {
        return;
    }
    const TermMask h3d = termBit(EntropyTerm::H3D);
    const bool has3d = (m_tracked & h3d) != 0;
    const bool has_marginals = (m_tracked & ~h3d) != 0;
    const auto marginals = [&]
    {
        if (has_marginals)
        {
            applyMarginalDeltas(changes, count, box);
        }
    };
    const auto cells3d = [&]
    {
        if (has3d)
        {
            apply3dDeltas(changes, count);
        }
    };
    // The 3D histogram and the marginal ones share nothing (each side has
    // its own histograms and scratch buffers): on two threads they are
    // updated side by side, with the same result as one after the other.
    if (splitsWork(points))
    {
        auto side = std::async(std::launch::async, marginals);
        cells3d();
        side.get();
    }
    else
    {
        marginals();
        cells3d();
    }
}

void IncrementalEntropyGrid::applyMarginalDeltas(
    const CellChange* changes, std::size_t count, const CellBox& box)
{
    // Marginal cells are shared by many observations: when one set of dense
    // grids covers every change, the net change of each cell is taken over
    // all of them (one sweep, and the updates of overlapping observations
    // cancel before reaching the histogram). Otherwise each observation on
    // its own: dense grids over its box, or hashed updates.
    if (applyMarginalDeltasDense(changes, count, box))
    {
        return;
    }
    const TermList terms(m_tracked);
    for (std::size_t c = 0; c < count; c++)
    {
        const CellChange& change = changes[c];
        const std::size_t n = change.cloud->size();
        if (n == 0 || applyMarginalDeltasDense(&change, 1, unionOf(change.from_box, change.to_box)))
        {
            continue;
        }
        packCells(change, m_marginal_keys);
        for (std::size_t k = 0; k < terms.n; k++)
        {
            const std::size_t t = terms.idx[k];
            if (t == static_cast<std::size_t>(EntropyTerm::H3D))
            {
                continue;
            }
            if (m_updates.size() < 2 * n)
            {  // grow only: shrinking and regrowing value-initialised it every time
                m_updates.resize(std::max(2 * n, 2 * m_updates.size()));
            }
            const std::size_t updates =
                collectChangedCells(t, change, m_marginal_keys.data(), m_updates.data());
            // Marginal cells collect many updates with large weights:
            // deferral evaluates w log w once per touched cell.
            m_hist[t].beginBatch(updates);
            m_hist[t].addDeferredMany(m_updates.data(), updates);
            m_hist[t].endBatch();
        }
    }
}

void IncrementalEntropyGrid::apply3dDeltas(const CellChange* changes, std::size_t count)
{
    const std::size_t t = static_cast<std::size_t>(EntropyTerm::H3D);
    std::size_t total = 0;
    for (std::size_t c = 0; c < count; c++)
    {
        total += 2 * changes[c].cloud->size();
    }
    if (m_pending3d.size() < total)
    {  // grow only (see above)
        m_pending3d.resize(std::max(total, 2 * m_pending3d.size()));
    }
    std::size_t pending = 0;
    for (std::size_t c = 0; c < count; c++)
    {
        if (changes[c].cloud->size() == 0)
        {
            continue;
        }
        packCells(changes[c], m_keys3d);
        pending +=
            collectChangedCells(t, changes[c], m_keys3d.data(), m_pending3d.data() + pending);
    }
    // 3D cells are mostly touched once and hold small integer weights:
    // immediate updates (table look-ups) beat deferral. All moved
    // observations at once: one call, one prefetching loop.
    addNetUpdates(t, m_pending3d.data(), pending);
}

IncrementalEntropyGrid::CellBox IncrementalEntropyGrid::unionOf(const CellBox& a, const CellBox& b)
{
    CellBox u;
    for (int k = 0; k < 3; k++)
    {
        u.lo[k] = std::min(a.lo[k], b.lo[k]);
        u.hi[k] = std::max(a.hi[k], b.hi[k]);
    }
    return u;
}

void IncrementalEntropyGrid::packCells(const CellChange& change, std::vector<std::uint64_t>& keys)
{
    const std::vector<CellIndex>& from = *change.from;
    const std::vector<CellIndex>& to = *change.to;
    const std::size_t n = change.cloud->size();
    keys.resize(2 * n);
    std::uint64_t* const kf = keys.data();
    std::uint64_t* const kt = kf + n;
    for (std::size_t j = 0; j < n; j++)
    {
        kf[j] = packCellKey(from[j].x, from[j].y, from[j].z);
        kt[j] = packCellKey(to[j].x, to[j].y, to[j].z);
    }
}

std::size_t IncrementalEntropyGrid::collectChangedCells(
    std::size_t t,
    const CellChange& change,
    const std::uint64_t* keys,
    WeightedHistogram::Update* u)
{
    // A term's key is the 3D key with the dropped axes' fields replaced by
    // the packed 0 (same bits as packCellKey() with those axes set to 0).
    constexpr std::uint64_t FIELD = (std::uint64_t{1} << 21) - 1;
    const std::uint64_t keep =  // all-ones fields for the kept axes
        (TERM_AXES[t][0] ? FIELD << 42 : 0) | (TERM_AXES[t][1] ? FIELD << 21 : 0) |
        (TERM_AXES[t][2] ? FIELD : 0);
    const std::uint64_t fill = packCellKey(0, 0, 0) & ~keep;
    const std::size_t n = change.cloud->size();
    const std::uint64_t* const kf = keys;
    const std::uint64_t* const kt = keys + n;
    const float* const wts = change.cloud->weights.data();
    // Branch-free: both updates are always written and kept only if the
    // projected cell changes (a data-dependent branch here mispredicts about
    // half of the time).
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
    return count;
}

}  // namespace emslam::maps
