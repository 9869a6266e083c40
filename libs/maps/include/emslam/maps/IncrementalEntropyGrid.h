// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/maps/EntropyEnergy.h>
#include <emslam/maps/WeightedHistogram.h>
#include <emslam/maps/WeightedPointCloud.h>

#include <mrpt/poses/CPose3D.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace emslam::maps
{
/** The incremental-entropy engine behind CEntropyVoxelMap (paper §2.2.1):
 * a set of posed, simplified observations binned at cell size l_d into the
 * weighted histograms of the tracked entropy terms (the 3D histogram and
 * its marginals on the principal planes and axes), whose entropies are kept
 * up to date as observations move.
 *
 * Moving an observation re-bins only its points whose cell changes: the
 * marginal terms through dense grids of weight deltas when the moved
 * observations' cells fit in a small box, otherwise through hashed bulk
 * updates; the 3D term through immediate updates. The last move can be
 * undone (revertLastMove()): the histograms replay their own undo logs, and
 * the observations swap their previous cells back.
 *
 * Plain C++ (no MRPT map base class); cells are computed in the map frame
 * from the observations' poses, cell = floor(T_world_obs · p / l_d).
 *
 * \ingroup emslam_maps_grp \sa CEntropyVoxelMap, WeightedHistogram
 */
class IncrementalEntropyGrid
{
public:
    /** One requested move: observation index and its new pose in the map. */
    struct ObservationMove
    {
        std::size_t index{0};       //!< index of the observation, in insertion order
        mrpt::poses::CPose3D pose;  //!< its new pose in the map
    };

    /** An observation as given to assignObservations(): a cloud in its own
     * frame and its pose in the map. */
    struct PosedCloud
    {
        WeightedPointCloud cloud;   //!< points in the observation's own frame
        mrpt::poses::CPose3D pose;  //!< the observation's pose in the map
    };

    /** Memory statistics, for reports and benchmarks. */
    struct MemoryStats
    {
        std::size_t occupied_cells_3d{0};  //!< occupied cells of the 3D histogram (if tracked)
        std::size_t histogram_bytes{0};    //!< all tracked histograms
        std::size_t observation_bytes{0};  //!< simplified clouds, poses, cell indices
        /** histogram_bytes / occupied cells summed over tracked histograms. */
        double bytes_per_occupied_cell{0};
    };

    /** An empty grid of cell size 0.15 m that tracks no term. */
    IncrementalEntropyGrid() = default;
    /** An empty grid; throws unless cell_size > 0. */
    IncrementalEntropyGrid(double cell_size, TermMask tracked);

    /** @name Grid */
    /** @{ */
    /** Cell size l_d [m]. */
    double cellSize() const { return m_cell_size; }
    /** Terms tracked incrementally. */
    TermMask trackedTerms() const { return m_tracked; }
    /** Sets the cell size and tracked terms (throws unless cell_size > 0)
     * and re-bins every observation; they keep their points (simplified at
     * the cell size of their insertion). */
    void setGrid(double cell_size, TermMask tracked);
    /** Cell indices of `cloud` at `pose` on this grid, as the observations'
     * cells are computed. */
    void computeCells(
        const WeightedPointCloud& cloud,
        const mrpt::poses::CPose3D& pose,
        std::vector<CellIndex>& out) const;
    /** @} */

    /** @name Observations and moves */
    /** @{ */
    /** Adds a weighted cloud given in its own frame at pose `T_world_obs`;
     * it is simplified at l_d (§2.2.2) unless `already_simplified` (then it
     * is only sorted by cell; stored points are always in cell order, which
     * makes moves cache friendly). Forgets the undo record. Returns the new
     * observation's index. */
    std::size_t addObservation(
        const WeightedPointCloud& cloud,
        const mrpt::poses::CPose3D& T_world_obs,
        bool already_simplified = false);
    /** Replaces every observation by `observations`, kept as given (neither
     * simplified nor reordered), with the grid set as by setGrid(), and
     * rebuilds the histograms (used when loading a map). */
    void assignObservations(
        double cell_size, TermMask tracked, std::vector<PosedCloud> observations);
    /** Removes every observation. */
    void clear();
    /** Number of observations. */
    std::size_t observationCount() const { return m_obs.size(); }
    /** Current pose of observation `i` in the map (throws if out of range). */
    const mrpt::poses::CPose3D& observationPose(std::size_t i) const;
    /** Simplified cloud of observation `i`, in its own frame (throws if out
     * of range). */
    const WeightedPointCloud& observationCloud(std::size_t i) const;
    /** Moves observation `i` to `T_world_obs`; returns the new energy.
     * Starts a new undo record (see revertLastMove()). */
    double moveObservation(std::size_t i, const mrpt::poses::CPose3D& T_world_obs);
    /** Moves several observations at once (one undo record); returns the new
     * energy. An index may appear more than once (the last pose wins).
     * Throws, changing nothing, if an index is out of range. */
    double moveObservations(const std::vector<ObservationMove>& moves);
    /** True if the last moveObservation(s) can still be undone. */
    bool canRevert() const { return m_undo_count > 0; }
    /** Undoes the last moveObservation(s) call (poses, cells and entropies
     * return to their previous values exactly up to rounding); returns the
     * energy. Throws if there is nothing to revert. */
    double revertLastMove();
    /** Forgets the undo record. */
    void commitMove();
    /** Threads of one move (1 or 2; throws otherwise). With 2, when the 3D
     * term and marginal ones are tracked (Exp. 9, 10), a move, an undo or
     * energyAtPoses() over at least PARALLEL_MIN_POINTS points bins the
     * observations in two halves and updates the 3D histogram and the
     * marginal ones side by side; the results are the same as with 1. */
    void setThreads(int threads);
    /** Threads of one move (see setThreads()). */
    int threads() const { return m_threads; }
    /** Smallest move that setThreads(2) splits: below it, starting a
     * thread costs more than it saves. */
    static constexpr std::size_t PARALLEL_MIN_POINTS = 16384;
    /** @} */

    /** @name Entropies and energy */
    /** @{ */
    /** Sum of the tracked entropies [nats] (O(1): running sums). */
    double energy() const;
    /** One entropy [nats]: O(1) if tracked, otherwise built from scratch. */
    double entropy(EntropyTerm t) const;
    /** All seven entropies (untracked ones from scratch). */
    EntropyTerms entropies() const;
    /** All seven entropies recomputed from scratch from the observations and
     * their poses (for checks; O(total points)). */
    EntropyTerms computeEntropiesFromScratch() const;
    /** Clears and rebuilds the tracked histograms from all observations and
     * their current poses; returns the energy (the "full evaluation"). */
    double recomputeFromScratch();
    /** The energy with observation i at poses[i] (one pose per observation),
     * from scratch as recomputeFromScratch() would give it; the grid does
     * not change. Throws if the sizes differ. */
    double energyAtPoses(const std::vector<mrpt::poses::CPose3D>& poses) const;
    /** Tracked histogram of a term (nullptr if not tracked). */
    const WeightedHistogram* trackedHistogram(EntropyTerm t) const;
    /** Builds the histogram of any term from scratch. */
    WeightedHistogram buildHistogram(EntropyTerm t) const;
    /** Total weight W of the observations. */
    double totalWeight() const { return m_total_weight; }
    /** Memory statistics. */
    MemoryStats memoryStats() const;
    /** @} */

private:
    /** Bounding box of a set of cells (inclusive; empty if hi < lo). */
    struct CellBox
    {
        std::int32_t lo[3]{0, 0, 0};
        std::int32_t hi[3]{-1, -1, -1};
    };
    struct Observation
    {
        WeightedPointCloud cloud;      //!< simplified, own frame
        mrpt::poses::CPose3D pose;     //!< T_world_obs
        std::vector<CellIndex> cells;  //!< current cell of each point
        CellBox box;                   //!< bounding box of `cells`
        double weight_sum{0};          //!< cloud.totalWeight()
        bool integral_weights{false};  //!< cloud.hasIntegralWeights()
    };
    /** Sets the cached weight statistics of `o` from its cloud. */
    static void setWeightStats(Observation& o);
    struct UndoEntry
    {
        std::size_t index{0};
        mrpt::poses::CPose3D old_pose;
        std::vector<CellIndex> cells;  //!< buffer: old cells after a move
        CellBox box;                   //!< bounding box of `cells`
    };
    /** One observation going from one cell assignment to another. */
    struct CellChange
    {
        const WeightedPointCloud* cloud{nullptr};
        const std::vector<CellIndex>* from{nullptr};
        const std::vector<CellIndex>* to{nullptr};
        CellBox from_box;  //!< bounding box of *from
        CellBox to_box;    //!< bounding box of *to
    };

    /** computeCells(), also giving the cells' bounding box if `box`. */
    void computeCells(
        const WeightedPointCloud& cloud,
        const mrpt::poses::CPose3D& pose,
        std::vector<CellIndex>& out,
        CellBox* box) const;
    /** Adds (sign +1) or removes (−1) an observation's weights to/from the tracked histograms. */
    void addToTracked(const Observation& o, double sign);
    /** Applies the changes of distinct observations to every tracked term. */
    void applyCellDeltas(const CellChange* changes, std::size_t count);
    /** The marginal terms' part of applyCellDeltas(); `box` holds every
     * from and to cell. Touches only the marginal histograms, m_updates,
     * m_marginal_keys, m_dense and m_fields. */
    void applyMarginalDeltas(const CellChange* changes, std::size_t count, const CellBox& box);
    /** The 3D term's part of applyCellDeltas(). Touches only the 3D
     * histogram, m_keys3d and m_pending3d. */
    void apply3dDeltas(const CellChange* changes, std::size_t count);
    /** Packed keys of a change's cells: [0, n) from, [n, 2n) to. */
    static void packCells(const CellChange& change, std::vector<std::uint64_t>& keys);
    /** Writes to `u` the (cell, ±w) updates of term `t` for the points of
     * `change` whose projected cell changes (`keys` from packCells(); `u`
     * has room for 2n); returns their number. */
    static std::size_t collectChangedCells(
        std::size_t t,
        const CellChange& change,
        const std::uint64_t* keys,
        WeightedHistogram::Update* u);
    static CellBox unionOf(const CellBox& a, const CellBox& b);
    /** True if index(0..count-1) has no repeated value. */
    template <typename INDEX>
    bool distinctIndices(std::size_t count, INDEX&& index);
    /** Applies updates to term `t` (addManyIntegral() if m_integral_weights). */
    void addNetUpdates(std::size_t t, const WeightedHistogram::Update* u, std::size_t count);
    /** The marginal terms of `changes` through dense grids of weight deltas
     * over `box` (which contains every from and to cell); false (nothing
     * done) if a grid would be too large or the terms have no dense path. */
    bool applyMarginalDeltasDense(const CellChange* changes, std::size_t count, const CellBox& box);
    /** True if a move of `points` points is split over two threads (see
     * setThreads()). */
    bool splitsWork(std::size_t points) const;
    /** Fills the empty histograms `hist` of the tracked terms with every
     * observation's weights at `cells` (one list per observation);
     * `scratch` is a work buffer. */
    void fillTracked(
        const std::vector<const std::vector<CellIndex>*>& cells,
        std::array<WeightedHistogram, NUM_ENTROPY_TERMS>& hist,
        std::vector<WeightedHistogram::Update>& scratch) const;
    /** Starts deferred batches on the tracked histograms. */
    void beginBatches(std::size_t max_new_cells);
    /** Ends the batches started by beginBatches(). */
    void endBatches();
    void resetTracked();
    /** Ends the histograms' undo records (see WeightedHistogram::rollback()). */
    void dropHistogramUndo();

    double m_cell_size{0.15};
    TermMask m_tracked{0};
    std::array<WeightedHistogram, NUM_ENTROPY_TERMS> m_hist;
    std::vector<Observation> m_obs;
    std::vector<UndoEntry> m_undo;  //!< entries [0, m_undo_count) are live; buffers are reused
    std::size_t m_undo_count{0};
    std::vector<WeightedHistogram::Update> m_updates;    //!< scratch of the marginal updates
    std::vector<WeightedHistogram::Update> m_pending3d;  //!< scratch of apply3dDeltas()
    std::vector<std::uint64_t> m_keys3d;         //!< scratch of apply3dDeltas(): packed cells
    std::vector<std::uint64_t> m_marginal_keys;  //!< scratch of applyMarginalDeltas()
    std::vector<double> m_dense;  //!< scratch of applyMarginalDeltasDense(): grids, kept zero
    std::vector<std::uint64_t> m_fields;  //!< scratch of applyMarginalDeltasDense(): key fields
    std::vector<CellChange> m_changes;    //!< scratch of moves and reverts
    std::vector<std::uint8_t> m_seen;     //!< scratch of distinctIndices()
    double m_total_weight{0};
    /** Every observation weight is an integer ≤ 2^24 (point counts): cell
     * weights are then exact integer sums and moves use
     * WeightedHistogram::addManyIntegral(). */
    bool m_integral_weights{true};
    int m_threads{1};  //!< see setThreads()
};

}  // namespace emslam::maps
