// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/maps/EntropyEnergy.h>
#include <emslam/maps/IncrementalEntropyGrid.h>
#include <emslam/maps/WeightedHistogram.h>
#include <emslam/maps/WeightedPointCloud.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMetricMap.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <vector>

namespace emslam
{
/** The entropy map of the paper (§2.2.1-2.2.2): the observations of a
 * trajectory, each simplified at cell size l_d and kept with its pose, binned
 * into a weighted 3D voxel histogram and its marginals on the principal planes
 * (XY, XZ, YZ) and axes (X, Y, Z). Its consistency energy (Exp. 8-12) is what
 * the rectifier minimises by moving observations.
 *
 * **Frames.** The map (world) frame is the first camera's optical frame:
 * x right, y down (Y is vertical), z forward; XZ is the horizontal plane.
 * An observation inserted with `insertObservation(obs, robotPose)` follows
 * MRPT's convention: its points are brought to the robot frame with the
 * observation's `sensorPose`, simplified there, and the observation's pose in
 * the map is `robotPose` (identity if not given). So, when the "robot" is the
 * camera (T_world_cam, optical axes), a `CObservation3DRangeScan` whose points
 * are in MRPT's sensor frame (+X forward, +Y left, +Z up, e.g. from
 * emslam::stereo::toRangeScan()) needs `sensorPose = opticalFromMrptSensor()`
 * (a pure rotation), and moveObservation() then takes camera poses.
 *
 * **Observations accepted:** `CObservation3DRangeScan` (its 3D points, or the
 * range image unprojected if it has none), `CObservationPointCloud` (weights
 * taken from a `CWeightedPointsMap` cloud), and weighted clouds of our own code
 * through insertWeightedCloud(). Every insertion creates one movable
 * observation.
 *
 * **Moving observations.** moveObservation() / moveObservations() re-bin only
 * the moved observations (the cells whose key changes) and update every
 * tracked entropy incrementally; revertLastMove() undoes the last call. The
 * tracked terms are the ones of the configured energy; entropies() computes
 * the others from scratch. The map is an MRPT adapter (options, insertion of
 * MRPT observations, serialization, drawing, likelihood) around the engine
 * that does this work, emslam::maps::IncrementalEntropyGrid.
 *
 * **INI** (a CMultiMetricMap block; `<P>` = `<section>_entropyVoxelMap_00`):
 * \code
 * [<section>]
 * entropyVoxelMap_count = 1          ; also "CEntropyVoxelMap" or "emslam::CEntropyVoxelMap"
 *
 * [<P>_creationOpts]
 * cell_size = 0.15                   ; l_d [m], 0.01..100 (paper: 0.15 indoor, 0.35 outdoor)
 * energy    = structured             ; unstructured | low_structured | structured (6DOF)
 *                                    ; planar_low_structured | planar_structured (3DOF)
 * dof       = 6                      ; 3 or 6; must match the energy (absent: follows it)
 * enableSaveAs3DObject = true        ; (MRPT generic map keys, optional)
 *
 * [<P>_insertOpts]
 * max_range  = 20.0                  ; points farther from the sensor are dropped [m]; 0 = no limit
 * min_range  = 0.0                   ; points nearer are dropped [m]
 * decimation = 1                     ; use one point in N (≥ 1)
 *
 * [<P>_drawOpts]
 * max_cubes     = 50000              ; draw at most this many (densest) cells
 * min_cube_size = 0.15               ; cube edge of the sparsest cell, as a fraction of l_d
 * \endcode
 *
 * \ingroup emslam_maps_grp \sa emslam::maps::IncrementalEntropyGrid,
 * emslam::maps::WeightedHistogram, emslam::maps::EnergyType
 */
class CEntropyVoxelMap : public mrpt::maps::CMetricMap
{
    DEFINE_SERIALIZABLE(CEntropyVoxelMap, emslam)

public:
    /** Creation options (`_creationOpts` section). */
    struct TCreationOptions : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws, naming the INI key, if a value is invalid. */
        void validate() const;

        /** Cell size l_d [m] of the histograms and of the observation
         * simplification. (Default: 0.15; paper: 0.15 indoor, 0.35 outdoor) */
        double cell_size{0.15};
        /** Consistency energy, Exp. 8-12. (Default: structured) */
        emslam::maps::EnergyType energy{emslam::maps::EnergyType::Structured};
        /** Degrees of freedom of the trajectory: 3 or 6. (Default: 6) */
        int dof{6};
    };

    /** Insertion options (`_insertOpts` section). */
    struct TInsertionOptions : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws, naming the INI key, if a value is invalid. */
        void validate() const;

        /** Points farther than this from the sensor are ignored [m]; 0: no
         * limit. (Default: 20.0) */
        double max_range{20.0};
        /** Points nearer than this to the sensor are ignored [m]. (Default: 0.0) */
        double min_range{0.0};
        /** Only one point in `decimation` is used (≥ 1). (Default: 1) */
        int decimation{1};
    };

    /** Drawing options (`_drawOpts` section). */
    struct TDrawOptions : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws, naming the INI key, if a value is invalid. */
        void validate() const;

        /** Draw at most this many cells (the densest). (Default: 50000) */
        int max_cubes{50000};
        /** Cube edge of the sparsest cell as a fraction of l_d, in (0,1];
         * the densest is l_d. (Default: 0.15) */
        double min_cube_size{0.15};
    };

    /** One requested move: observation index and its new pose in the map. */
    using ObservationMove = emslam::maps::IncrementalEntropyGrid::ObservationMove;

    /** Memory statistics, for reports and benchmarks. */
    using MemoryStats = emslam::maps::IncrementalEntropyGrid::MemoryStats;

    /** Creates an empty map with default options. */
    CEntropyVoxelMap();
    /** Creates an empty map; validates the options. */
    explicit CEntropyVoxelMap(const TCreationOptions& creation);
    /** Creates an empty map; validates the options. */
    CEntropyVoxelMap(const TCreationOptions& creation, const TInsertionOptions& insertion);

    /** @name Options */
    /** @{ */
    /** Current creation options. */
    const TCreationOptions& creationOptions() const { return m_creation; }
    /** Sets new creation options (validated) and re-bins every observation.
     * Observations keep the simplification done at insertion time. */
    void setCreationOptions(const TCreationOptions& o);
    TInsertionOptions insertionOptions;  //!< Used by the next insertions
    TDrawOptions drawOptions;            //!< Used by getVisualizationInto()
    /** @} */

    /** @name Observations and moves (the rectifier's API) */
    /** @{ */
    /** Inserts a weighted cloud given in its own frame at pose `T_world_obs`;
     * it is simplified at l_d (§2.2.2) unless `already_simplified` (then it
     * is only sorted by cell; stored points are always in cell order, which
     * makes moves cache friendly). Returns the new observation's index. */
    std::size_t insertWeightedCloud(
        const emslam::maps::WeightedPointCloud& cloud,
        const mrpt::poses::CPose3D& T_world_obs,
        bool already_simplified = false);
    /** Number of observations. */
    std::size_t observationCount() const { return m_engine.observationCount(); }
    /** Current pose of observation `i` in the map. */
    const mrpt::poses::CPose3D& observationPose(std::size_t i) const;
    /** Simplified cloud of observation `i`, in its own frame. */
    const emslam::maps::WeightedPointCloud& observationCloud(std::size_t i) const;
    /** Moves observation `i` to `T_world_obs`; returns the new energy.
     * Starts a new undo record (see revertLastMove()). */
    double moveObservation(std::size_t i, const mrpt::poses::CPose3D& T_world_obs);
    /** Moves several observations at once (one undo record); returns the new
     * energy. An index may appear more than once (the last pose wins). */
    double moveObservations(const std::vector<ObservationMove>& moves);
    /** True if the last moveObservation(s) can still be undone. */
    bool canRevert() const { return m_engine.canRevert(); }
    /** Undoes the last moveObservation(s) call (poses, cells and entropies
     * return to their previous values exactly up to rounding); returns the
     * energy. Throws if there is nothing to revert. */
    double revertLastMove();
    /** Forgets the undo record (called by insertions and clear()). */
    void commitMove() { m_engine.commitMove(); }
    /** Threads of one move, 1 or 2 (see IncrementalEntropyGrid::setThreads()). */
    void setThreads(int threads) { m_engine.setThreads(threads); }
    /** Threads of one move. */
    int threads() const { return m_engine.threads(); }
    /** @} */

    /** @name Entropies and energy */
    /** @{ */
    /** Energy of the configured expression (O(1): running sums). */
    double energy() const { return m_engine.energy(); }
    /** Terms tracked incrementally (those of the configured energy). */
    emslam::maps::TermMask trackedTerms() const { return m_engine.trackedTerms(); }
    /** One entropy [nats]: O(1) if tracked, otherwise built from scratch. */
    double entropy(emslam::maps::EntropyTerm t) const { return m_engine.entropy(t); }
    /** All seven entropies (untracked ones from scratch). */
    emslam::maps::EntropyTerms entropies() const { return m_engine.entropies(); }
    /** All seven entropies recomputed from scratch from the observations and
     * their poses (for checks; O(total points)). */
    emslam::maps::EntropyTerms computeEntropiesFromScratch() const
    {
        return m_engine.computeEntropiesFromScratch();
    }
    /** Clears and rebuilds the tracked histograms from all observations and
     * their current poses; returns the energy (the "full evaluation"). */
    double recomputeFromScratch() { return m_engine.recomputeFromScratch(); }
    /** The energy with observation i at poses[i], one pose per observation
     * (e.g. the map on a shifted grid, or another trajectory), computed from
     * scratch; the map does not change. */
    double energyAtPoses(const std::vector<mrpt::poses::CPose3D>& poses) const
    {
        return m_engine.energyAtPoses(poses);
    }
    /** Tracked histogram of a term (nullptr if not tracked). */
    const emslam::maps::WeightedHistogram* trackedHistogram(emslam::maps::EntropyTerm t) const
    {
        return m_engine.trackedHistogram(t);
    }
    /** Builds the histogram of any term from scratch. */
    emslam::maps::WeightedHistogram buildHistogram(emslam::maps::EntropyTerm t) const
    {
        return m_engine.buildHistogram(t);
    }
    /** Total weight W of the map. */
    double totalWeight() const { return m_engine.totalWeight(); }
    /** Memory statistics. */
    MemoryStats memoryStats() const { return m_engine.memoryStats(); }
    /** The engine holding the observations and the tracked histograms. */
    const emslam::maps::IncrementalEntropyGrid& engine() const { return m_engine; }
    /** @} */

    /** Pose of MRPT's sensor frame (+X forward, +Y left, +Z up) in the optical
     * frame (x right, y down, z forward): set it as the `sensorPose` of a
     * CObservation3DRangeScan whose robot pose is an optical camera pose. */
    static mrpt::poses::CPose3D opticalFromMrptSensor();

    /** @name CMetricMap interface */
    /** @{ */
    bool isEmpty() const override { return m_engine.observationCount() == 0; }
    /** Writes `<prefix>_cells.txt` (x y z weight of each 3D cell) and
     * `<prefix>.3Dscene` (getVisualizationInto()). */
    void saveMetricMapRepresentationToFile(const std::string& filNamePrefix) const override;
    /** Occupied 3D cells as cubes (one CSetOfTriangles) whose edge and colour
     * follow the local density (paper Fig. 9 left): edge ∝ cube root of the
     * weight (volume ∝ density), colour from dark blue (sparse) to yellow
     * (dense). */
    void getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const override;
    std::string asString() const override;
    /** @} */

protected:
    /** Removes every observation (CMetricMap::clear()). */
    void internal_clear() override;
    /** Inserts a CObservation3DRangeScan or CObservationPointCloud at `robotPose` (identity if
     * none); false for other classes. */
    bool internal_insertObservation(
        const mrpt::obs::CObservation& obs,
        const std::optional<const mrpt::poses::CPose3D>& robotPose = std::nullopt) override;
    /** Log-likelihood [nats] of `obs` at `takenFrom`, from how much adding
     * it would raise the map entropy beyond its own. With the general-term
     * histogram (3D for 6DOF energies, XZ for 3DOF) and the code length
     * C(X) = W_X·H(X) of a weighted histogram,
     * logL = C(A) + C(O) − C(A ∪ O) ≤ 0,
     * i.e. −(W_A + W_O) times the weighted Jensen-Shannon divergence between
     * the map's and the observation's cell distributions: 0 when the
     * observation lands exactly on the map's density, lower the more new or
     * sparse cells it occupies. The map is not modified. */
    double internal_computeObservationLikelihood(
        const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
    /** True for the classes internal_insertObservation() takes: CObservation3DRangeScan,
     * CObservationPointCloud. */
    bool internal_canComputeObservationLikelihood(
        const mrpt::obs::CObservation& obs) const override;

private:
    /** Converts an MRPT observation to a cloud in the robot frame (sensorPose
     * applied, range and decimation filters); false if unsupported. */
    bool observationToCloud(
        const mrpt::obs::CObservation& obs, emslam::maps::WeightedPointCloud& out) const;
    /** Throws, naming `caller`, if `i` is not an observation index. */
    void requireIndex(std::size_t i, const char* caller) const;

    TCreationOptions m_creation;
    emslam::maps::IncrementalEntropyGrid m_engine;

    MAP_DEFINITION_START(CEntropyVoxelMap)
    emslam::CEntropyVoxelMap::TCreationOptions creationOpts;    //!< `_creationOpts`
    emslam::CEntropyVoxelMap::TInsertionOptions insertionOpts;  //!< `_insertOpts`
    emslam::CEntropyVoxelMap::TDrawOptions drawOpts;            //!< `_drawOpts`
    MAP_DEFINITION_END(CEntropyVoxelMap)
};

}  // namespace emslam

namespace emslam::maps
{
/** The map class under the library's namespace (its RTTI / INI name stays
 * `emslam::CEntropyVoxelMap`). \ingroup emslam_maps_grp */
using CEntropyVoxelMap = emslam::CEntropyVoxelMap;
}  // namespace emslam::maps
