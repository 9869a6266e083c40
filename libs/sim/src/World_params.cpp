// SPDX-License-Identifier: BSD-3-Clause
// World's generator parameters ([Building], [Ground], [Terrain]): loading,
// saving and the checks that name the section and key of a bad value.
#include "WorldDetail.h"

#include <emslam/sim/World.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace emslam::sim
{
// ---------------------------------------------------------------- key checks
namespace detail
{
[[noreturn]] void badKey(const std::string& section, const std::string& key, const std::string& msg)
{
    throw std::invalid_argument("[" + section + "] " + key + ": " + msg);
}

void requirePositive(double v, const std::string& section, const std::string& key)
{
    if (!(v > 0.0) || !std::isfinite(v))
    {
        badKey(section, key, "must be > 0 (got " + std::to_string(v) + ")");
    }
}

/** `v` finite and within [lo, hi]. */
void requireRange(
    double v, double lo, double hi, const std::string& section, const std::string& key)
{
    if (!(v >= lo && v <= hi))
    {
        badKey(
            section, key,
            "must be in [" + mrpt::format("%g", lo) + ", " + mrpt::format("%g", hi) + "] (got " +
                mrpt::format("%g", v) + ")");
    }
}

void requireTexture(const std::string& kind, const std::string& section, const std::string& key)
{
    if (!ProceduralTexture::isKnownKind(kind))
    {
        badKey(
            section, key,
            "unknown texture kind '" + kind + "' (expected " + ProceduralTexture::knownKinds() +
                ")");
    }
}
}  // namespace detail

using detail::badKey;
using detail::requirePositive;
using detail::requireRange;
using detail::requireTexture;

// ---------------------------------------------------------------- parameters
namespace
{
/** Every key of the section, once for load and save. */
void visit(World::TBuildingParams& p, emslam::util::ConfigVisitor& v)
{
    v.field("cell_size", p.cell_size);
    v.field("wall_height", p.wall_height);
    v.field("level_height", p.level_height);
    v.field("levels", p.levels);
    v.field("map_0", p.map_0);
    v.field("map_1", p.map_1);
    v.field("stairs_dir", p.stairs_dir);
    v.field("door_probability", p.door_probability);
    v.field("poster_probability", p.poster_probability);
    v.field("wall_texture", p.wall_texture);
    v.field("floor_texture", p.floor_texture);
    v.field("ceiling_texture", p.ceiling_texture);
    v.field("texel_size", p.texel_size);
}

void visit(World::TGroundParams& p, emslam::util::ConfigVisitor& v)
{
    v.field("extent", p.extent);
    v.field("objects", p.objects);
    v.field("min_size", p.min_size);
    v.field("max_size", p.max_size);
    v.field("clearance", p.clearance);
    v.field("ground_texture", p.ground_texture);
    v.field("object_texture", p.object_texture);
    v.field("texel_size", p.texel_size);
}

void visit(World::TTerrainParams& p, emslam::util::ConfigVisitor& v)
{
    v.field("extent", p.extent);
    v.field("cell", p.cell);
    v.field("amplitude", p.amplitude);
    v.field("channel_depth", p.channel_depth);
    v.field("channel_width", p.channel_width);
    v.field("rocks", p.rocks);
    v.field("bushes", p.bushes);
    v.field("clearance", p.clearance);
    v.field("ground_texture", p.ground_texture);
    v.field("texel_size", p.texel_size);
}
}  // namespace

void World::TBuildingParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    requirePositive(cell_size, s, "cell_size");
    requirePositive(wall_height, s, "wall_height");
    requirePositive(level_height, s, "level_height");
    requirePositive(texel_size, s, "texel_size");
    if (levels != 1 && levels != 2)
    {
        badKey(s, "levels", "must be 1 or 2 (got " + std::to_string(levels) + ")");
    }
    if (map_0.empty())
    {
        badKey(s, "map_0", "the level-0 floor plan is empty");
    }
    if (levels == 2 && map_1.empty())
    {
        badKey(s, "map_1", "levels = 2 needs a level-1 floor plan");
    }
    if (stairsDirections().empty())
    {
        badKey(s, "stairs_dir", "expected +x, -x, +z or -z (one per staircase), got ''");
    }
    for (const auto& d : stairsDirections())
    {
        if (d != "+x" && d != "-x" && d != "+z" && d != "-z")
        {
            badKey(
                s, "stairs_dir",
                "expected +x, -x, +z or -z (one per staircase), got '" + stairs_dir + "'");
        }
    }
    requireRange(door_probability, 0, 1, s, "door_probability");
    requireRange(poster_probability, 0, 1, s, "poster_probability");
    requireTexture(wall_texture, s, "wall_texture");
    requireTexture(floor_texture, s, "floor_texture");
    requireTexture(ceiling_texture, s, "ceiling_texture");
}

void World::TBuildingParams::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

std::vector<std::string> World::TBuildingParams::stairsDirections() const
{
    std::vector<std::string> dirs;
    std::istringstream in(stairs_dir);
    for (std::string d; in >> d;)
    {
        dirs.push_back(d);
    }
    return dirs;
}

void World::TGroundParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    requirePositive(extent, s, "extent");
    requirePositive(min_size, s, "min_size");
    requirePositive(texel_size, s, "texel_size");
    if (!(max_size >= min_size && max_size <= 1e4))
    {
        badKey(
            s, "max_size", "must be in [min_size, 1e4] m (got " + std::to_string(max_size) + ")");
    }
    requireRange(clearance, 0, 1e4, s, "clearance");
    // Placement tries 50 positions per object in an int.
    requireRange(objects, 0, 100000, s, "objects");
    requireTexture(ground_texture, s, "ground_texture");
    requireTexture(object_texture, s, "object_texture");
}

void World::TGroundParams::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void World::TTerrainParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    requirePositive(extent, s, "extent");
    requirePositive(cell, s, "cell");
    requirePositive(channel_width, s, "channel_width");
    requirePositive(texel_size, s, "texel_size");
    if (extent / cell > 2000)
    {
        badKey(s, "cell", "too small for the extent (more than 2000 samples per side)");
    }
    requireRange(amplitude, -1e3, 1e3, s, "amplitude");
    requireRange(channel_depth, -1e3, 1e3, s, "channel_depth");
    requireRange(clearance, 0, 1e4, s, "clearance");
    // Placement tries 50 positions per rock in an int.
    requireRange(rocks, 0, 100000, s, "rocks");
    requireRange(bushes, 0, 100000, s, "bushes");
    requireTexture(ground_texture, s, "ground_texture");
}

void World::TTerrainParams::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

}  // namespace emslam::sim
