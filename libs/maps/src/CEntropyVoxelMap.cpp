// SPDX-License-Identifier: BSD-3-Clause
// CEntropyVoxelMap: construction, options, INI map definition, insertion, and
// the observation API forwarded to the engine.
#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/maps/CWeightedPointsMap.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

using emslam::CEntropyVoxelMap;
using emslam::maps::EnergyType;
using emslam::maps::WeightedPointCloud;

// INI names: "entropyVoxelMap" (alias), "CEntropyVoxelMap", full RTTI name.
MAP_DEFINITION_REGISTER(
    "emslam::CEntropyVoxelMap,CEntropyVoxelMap,entropyVoxelMap", emslam::CEntropyVoxelMap)

// ---------------------------------------------------------------- options --

namespace
{
/** Refuses a value of `key` that is not a number (`whole`: an int) as a
 * whole: MRPT's read_double() / read_int() read "12abc" as 12 and "abc" as 0,
 * and MRPT's own tools (observations2map) load these options unchecked. */
void requireNumberText(
    const mrpt::config::CConfigFileBase& c, const std::string& s, const char* key, bool whole)
{
    if (!c.keyExists(s, key))
    {
        return;
    }
    const std::string t = c.read_string(s, key, "");
    char* end = nullptr;
    errno = 0;
    bool ok = false;
    if (whole)
    {
        const long long v = std::strtoll(t.c_str(), &end, 10);
        ok = errno == 0 && v >= std::numeric_limits<int>::min() &&
             v <= std::numeric_limits<int>::max();
    }
    else
    {
        (void)std::strtod(t.c_str(), &end);
        ok = true;
    }
    if (!ok || t.empty() || *end != '\0')
    {
        THROW_EXCEPTION_FMT(
            "CEntropyVoxelMap: invalid '%s' = '%s' in [%s] (must be %s)", key, t.c_str(), s.c_str(),
            whole ? "a whole number" : "a number");
    }
}
}  // namespace

namespace
{
/** Every key of the section, once for load and save. */
void visit(CEntropyVoxelMap::TCreationOptions& p, emslam::util::ConfigVisitor& v)
{
    v.field("cell_size", p.cell_size, "Cell size l_d [m] (paper: 0.15 indoor, 0.35 outdoor)");
    v.text(
        "energy", p.energy, [](emslam::maps::EnergyType e) { return emslam::maps::toString(e); },
        [](const std::string& t) { return emslam::maps::energyTypeFromString(t, "energy"); },
        "unstructured|low_structured|structured (6DOF), planar_low_structured|"
        "planar_structured (3DOF)");
    // Without a `dof` key the energy decides (3DOF energies imply dof = 3).
    if (v.loading() && !v.input().keyExists(v.section(), "dof"))
    {
        p.dof = emslam::maps::energyDof(p.energy);
    }
    v.field("dof", p.dof, "Degrees of freedom: 3 or 6 (must match the energy)");
}
}  // namespace

void CEntropyVoxelMap::TCreationOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    requireNumberText(c, s, "cell_size", false);
    requireNumberText(c, s, "dof", true);
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void CEntropyVoxelMap::TCreationOptions::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void CEntropyVoxelMap::TCreationOptions::validate() const
{
    // Cell keys hold +-2^20 cells per axis: +-10 km at the smallest l_d.
    if (!(cell_size > 0) || !std::isfinite(cell_size) || cell_size < 0.01 || cell_size > 100)
    {
        THROW_EXCEPTION_FMT(
            "CEntropyVoxelMap: invalid 'cell_size' = %g (must be > 0 [m], in [0.01, 100])",
            cell_size);
    }
    if (dof != 3 && dof != 6)
    {
        THROW_EXCEPTION_FMT("CEntropyVoxelMap: invalid 'dof' = %d (must be 3 or 6)", dof);
    }
    const int edof = emslam::maps::energyDof(energy);
    if (edof != dof)
    {
        THROW_EXCEPTION_FMT(
            "CEntropyVoxelMap: 'energy' = '%s' (Exp. %d) is a %dDOF energy but 'dof' = %d",
            emslam::maps::toString(energy).c_str(), emslam::maps::energyExpression(energy), edof,
            dof);
    }
}

namespace
{
/** Every key of the section, once for load and save. */
void visit(CEntropyVoxelMap::TInsertionOptions& p, emslam::util::ConfigVisitor& v)
{
    v.field("max_range", p.max_range, "Farther points are dropped [m]; 0 = no limit");
    v.field("min_range", p.min_range, "Nearer points are dropped [m]");
    v.field("decimation", p.decimation, "Use one point in N (>= 1)");
}
}  // namespace

void CEntropyVoxelMap::TInsertionOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    requireNumberText(c, s, "max_range", false);
    requireNumberText(c, s, "min_range", false);
    requireNumberText(c, s, "decimation", true);
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void CEntropyVoxelMap::TInsertionOptions::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void CEntropyVoxelMap::TInsertionOptions::validate() const
{
    // 10 km: see [StereoMatcher] max_range; keeps cell indices far from int overflow.
    if (!(max_range >= 0 && max_range <= 10000))
    {
        THROW_EXCEPTION_FMT(
            "CEntropyVoxelMap: invalid 'max_range' = %g (must be in [0, 10000] m; 0 = no limit)",
            max_range);
    }
    if (!(min_range >= 0 && min_range < 10000) || (max_range > 0 && min_range >= max_range))
    {
        THROW_EXCEPTION_FMT(
            "CEntropyVoxelMap: invalid 'min_range' = %g (must be >= 0 and < max_range)", min_range);
    }
    if (decimation < 1 || decimation > 1000000)
    {
        THROW_EXCEPTION_FMT(
            "CEntropyVoxelMap: invalid 'decimation' = %d (must be in [1, 1000000])", decimation);
    }
}

namespace
{
/** Every key of the section, once for load and save. */
void visit(CEntropyVoxelMap::TDrawOptions& p, emslam::util::ConfigVisitor& v)
{
    v.field("max_cubes", p.max_cubes, "Draw at most this many (densest) cells");
    v.field("min_cube_size", p.min_cube_size, "Edge of the sparsest cube / l_d, in (0,1]");
}
}  // namespace

void CEntropyVoxelMap::TDrawOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    requireNumberText(c, s, "max_cubes", true);
    requireNumberText(c, s, "min_cube_size", false);
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void CEntropyVoxelMap::TDrawOptions::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void CEntropyVoxelMap::TDrawOptions::validate() const
{
    if (max_cubes < 0 || max_cubes > 100000000)
    {
        THROW_EXCEPTION_FMT(
            "CEntropyVoxelMap: invalid 'max_cubes' = %d (must be in [0, 100000000])", max_cubes);
    }
    if (!(min_cube_size > 0 && min_cube_size <= 1))
    {
        THROW_EXCEPTION_FMT(
            "CEntropyVoxelMap: invalid 'min_cube_size' = %g (must be in (0,1])", min_cube_size);
    }
}

// ----------------------------------------------------- INI map definition --

CEntropyVoxelMap::TMapDefinition::TMapDefinition() = default;

void CEntropyVoxelMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& src, const std::string& prefix)
{
    creationOpts.loadFromConfigFile(src, prefix + "_creationOpts");
    insertionOpts.loadFromConfigFile(src, prefix + "_insertOpts");
    drawOpts.loadFromConfigFile(src, prefix + "_drawOpts");
}

void CEntropyVoxelMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "---- [_creationOpts] ----\n";
    creationOpts.dumpToTextStream(out);
    out << "---- [_insertOpts] ----\n";
    insertionOpts.dumpToTextStream(out);
    out << "---- [_drawOpts] ----\n";
    drawOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CEntropyVoxelMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& def_base)
{
    const auto& def = dynamic_cast<const CEntropyVoxelMap::TMapDefinition&>(def_base);
    auto* m = new CEntropyVoxelMap(def.creationOpts, def.insertionOpts);
    m->drawOptions = def.drawOpts;
    return m;
}

// ----------------------------------------------------------- construction --

CEntropyVoxelMap::CEntropyVoxelMap() : CEntropyVoxelMap(TCreationOptions{}, TInsertionOptions{}) {}

CEntropyVoxelMap::CEntropyVoxelMap(const TCreationOptions& creation)
    : CEntropyVoxelMap(creation, TInsertionOptions{})
{
}

CEntropyVoxelMap::CEntropyVoxelMap(
    const TCreationOptions& creation, const TInsertionOptions& insertion)
    : insertionOptions(insertion)
{
    insertionOptions.validate();
    setCreationOptions(creation);
}

void CEntropyVoxelMap::setCreationOptions(const TCreationOptions& o)
{
    o.validate();
    m_creation = o;
    m_engine.setGrid(o.cell_size, emslam::maps::energyTerms(o.energy));
}

mrpt::poses::CPose3D CEntropyVoxelMap::opticalFromMrptSensor()
{
    // Columns: MRPT sensor axes (+X forward, +Y left, +Z up) in optical
    // coordinates (x right, y down, z forward).
    mrpt::math::CMatrixDouble44 T = mrpt::math::CMatrixDouble44::Zero();
    T(2, 0) = 1.0;   // sensor X = optical +z
    T(0, 1) = -1.0;  // sensor Y = optical -x
    T(1, 2) = -1.0;  // sensor Z = optical -y
    T(3, 3) = 1.0;
    return mrpt::poses::CPose3D(T);
}

void CEntropyVoxelMap::internal_clear()
{
    m_engine.clear();
}

// ------------------------------------------------- observations and moves --
// The engine checks its arguments too; the checks here keep the map's own
// error messages.

void CEntropyVoxelMap::requireIndex(std::size_t i, const char* caller) const
{
    if (i >= m_engine.observationCount())
    {
        THROW_EXCEPTION_FMT(
            "CEntropyVoxelMap::%s(): observation index %zu out of range (%zu observations)", caller,
            i, m_engine.observationCount());
    }
}

const mrpt::poses::CPose3D& CEntropyVoxelMap::observationPose(std::size_t i) const
{
    ASSERTMSG_(
        i < m_engine.observationCount(), "CEntropyVoxelMap::observationPose(): index out of range");
    return m_engine.observationPose(i);
}

const WeightedPointCloud& CEntropyVoxelMap::observationCloud(std::size_t i) const
{
    ASSERTMSG_(
        i < m_engine.observationCount(),
        "CEntropyVoxelMap::observationCloud(): index out of range");
    return m_engine.observationCloud(i);
}

double CEntropyVoxelMap::moveObservation(std::size_t i, const mrpt::poses::CPose3D& T_world_obs)
{
    requireIndex(i, "moveObservations");
    return m_engine.moveObservation(i, T_world_obs);
}

double CEntropyVoxelMap::moveObservations(const std::vector<ObservationMove>& moves)
{
    for (const auto& mv : moves)
    {
        requireIndex(mv.index, "moveObservations");
    }
    return m_engine.moveObservations(moves);
}

double CEntropyVoxelMap::revertLastMove()
{
    ASSERTMSG_(m_engine.canRevert(), "CEntropyVoxelMap::revertLastMove(): nothing to revert");
    return m_engine.revertLastMove();
}

std::string CEntropyVoxelMap::asString() const
{
    std::ostringstream ss;
    ss << "CEntropyVoxelMap: " << m_engine.observationCount()
       << " observations, W=" << m_engine.totalWeight() << ", l_d=" << m_creation.cell_size
       << " m, energy=" << emslam::maps::toString(m_creation.energy) << " (Exp. "
       << emslam::maps::energyExpression(m_creation.energy) << ") = " << energy();
    return ss.str();
}

// -------------------------------------------------------------- insertion --

std::size_t CEntropyVoxelMap::insertWeightedCloud(
    const WeightedPointCloud& cloud,
    const mrpt::poses::CPose3D& T_world_obs,
    bool already_simplified)
{
    ASSERTMSG_(
        cloud.weights.size() == cloud.points.size(),
        "CEntropyVoxelMap::insertWeightedCloud(): one weight per point is required");
    return m_engine.addObservation(cloud, T_world_obs, already_simplified);
}

bool CEntropyVoxelMap::observationToCloud(
    const mrpt::obs::CObservation& obs, WeightedPointCloud& out) const
{
    out = WeightedPointCloud();
    const float* xs = nullptr;
    const float* ys = nullptr;
    const float* zs = nullptr;
    const mrpt::maps::CPointsMap* weighted = nullptr;  // per-point weights, if any
    std::size_t n = 0;
    mrpt::poses::CPose3D sensor_pose;
    mrpt::maps::CSimplePointsMap unprojected;  // only for range images without points

    if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs))
    {
        sensor_pose = scan->sensorPose;
        if (scan->hasPoints3D)
        {
            xs = scan->points3D_x.data();
            ys = scan->points3D_y.data();
            zs = scan->points3D_z.data();
            n = scan->points3D_x.size();
            ASSERT_EQUAL_(scan->points3D_y.size(), n);
            ASSERT_EQUAL_(scan->points3D_z.size(), n);
        }
        else if (scan->hasRangeImage)
        {
            // unprojectInto() is non-const (lazy loading): work on a copy;
            // this path (a range image without 3D points) is not a hot one.
            mrpt::obs::CObservation3DRangeScan copy = *scan;
            mrpt::obs::T3DPointsProjectionParams pp;
            pp.takeIntoAccountSensorPoseOnRobot = false;
            copy.unprojectInto(unprojected, pp);
            xs = unprojected.getPointsBufferRef_x().data();
            ys = unprojected.getPointsBufferRef_y().data();
            zs = unprojected.getPointsBufferRef_z().data();
            n = unprojected.size();
        }
        else
        {
            return false;
        }
    }
    else if (const auto* pc = dynamic_cast<const mrpt::obs::CObservationPointCloud*>(&obs))
    {
        if (!pc->pointcloud)
        {
            return false;
        }
        sensor_pose = pc->sensorPose;
        xs = pc->pointcloud->getPointsBufferRef_x().data();
        ys = pc->pointcloud->getPointsBufferRef_y().data();
        zs = pc->pointcloud->getPointsBufferRef_z().data();
        n = pc->pointcloud->size();
        if (const auto* wm =
                dynamic_cast<const mrpt::maps::CWeightedPointsMap*>(pc->pointcloud.get()))
        {
            weighted = wm;
        }
    }
    else
    {
        return false;
    }

    const double max_r2 = insertionOptions.max_range > 0
                              ? insertionOptions.max_range * insertionOptions.max_range
                              : std::numeric_limits<double>::infinity();
    const double min_r2 = insertionOptions.min_range * insertionOptions.min_range;
    const auto step = static_cast<std::size_t>(insertionOptions.decimation);
    out.points.reserve(n / step + 1);
    out.weights.reserve(n / step + 1);
    for (std::size_t i = 0; i < n; i += step)
    {
        const double x = xs[i], y = ys[i], z = zs[i];
        const double r2 = x * x + y * y + z * z;
        if (!std::isfinite(r2) || r2 == 0.0 || r2 > max_r2 || r2 < min_r2)
        {
            continue;  // (0,0,0) marks an invalid point in MRPT range scans
        }
        double gx = 0, gy = 0, gz = 0;
        sensor_pose.composePoint(x, y, z, gx, gy, gz);
        const float w = weighted ? static_cast<float>(weighted->getPointWeight(i)) : 1.0f;
        if (w > 0)
        {
            out.push_back(
                mrpt::math::TPoint3Df(
                    static_cast<float>(gx), static_cast<float>(gy), static_cast<float>(gz)),
                w);
        }
    }
    return true;
}

bool CEntropyVoxelMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
    WeightedPointCloud cloud;
    if (!observationToCloud(obs, cloud))
    {
        return false;
    }
    insertWeightedCloud(cloud, robotPose ? *robotPose : mrpt::poses::CPose3D());
    return true;
}
