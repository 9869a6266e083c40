// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/sim/World.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <opencv2/imgproc.hpp>
#include <random>
#include <sstream>
#include <stdexcept>

namespace emslam::sim
{
namespace
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

/** A number key of an `[Element*]` section (no parameter struct checks
 * these): the whole text must be a number, unlike read_double()'s atof(). */
double readNumber(
    const mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& k, double def)
{
    if (!c.keyExists(s, k))
    {
        return def;
    }
    const std::string txt = c.read_string(s, k, "");
    char* end = nullptr;
    const double v = std::strtod(txt.c_str(), &end);
    if (txt.empty() || *end != '\0')
    {
        badKey(s, k, "expected a number, got '" + txt + "'");
    }
    return v;
}

Vec3 readVec3(const mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& k)
{
    const std::string txt = c.read_string(s, k, "");
    std::istringstream in(txt);
    Vec3 v{};
    if (!(in >> v[0] >> v[1] >> v[2]))
    {
        badKey(s, k, "expected three numbers 'x y z', got '" + txt + "'");
    }
    std::string extra;
    if (in >> extra)
    {
        badKey(s, k, "expected three numbers 'x y z', got '" + txt + "'");
    }
    return v;
}

/** Distance from (x, z) to the polyline through `pts`. */
double distanceToPath(double x, double z, const std::vector<std::array<double, 2>>& pts)
{
    double best = 1e30;
    for (std::size_t i = 0; i < pts.size(); ++i)
    {
        const auto& a = pts[i];
        const auto& b = pts[std::min(i + 1, pts.size() - 1)];
        const double dx = b[0] - a[0];
        const double dz = b[1] - a[1];
        const double l2 = dx * dx + dz * dz;
        double t = l2 > 0 ? ((x - a[0]) * dx + (z - a[1]) * dz) / l2 : 0.0;
        t = std::clamp(t, 0.0, 1.0);
        best = std::min(best, std::hypot(x - a[0] - t * dx, z - a[1] - t * dz));
    }
    return best;
}

std::uint64_t mix(std::uint64_t seed, std::uint64_t k)
{
    std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (k + 1);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

Element makePlane(int axis, const Vec3& lo, const Vec3& hi, int texture, double texel)
{
    Element e;
    e.kind = Element::Kind::Plane;
    e.axis = axis;
    e.lo = lo;
    e.hi = hi;
    e.texture = texture;
    e.texel_size = texel;
    return e;
}

Element makeBox(const Vec3& lo, const Vec3& hi, int texture, double texel)
{
    Element e;
    e.kind = Element::Kind::Box;
    e.lo = lo;
    e.hi = hi;
    e.texture = texture;
    e.texel_size = texel;
    return e;
}

std::vector<std::string> splitRows(const std::string& map)
{
    std::vector<std::string> rows;
    std::string cur;
    for (char ch : map)
    {
        if (ch == '/')
        {
            rows.push_back(cur);
            cur.clear();
        }
        else if (ch != ' ' && ch != '\t' && ch != '"')
        {
            cur += ch;
        }
    }
    if (!cur.empty())
    {
        rows.push_back(cur);
    }
    return rows;
}
}  // namespace

// ---------------------------------------------------------------- parameters
void World::TBuildingParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    MRPT_LOAD_CONFIG_VAR(cell_size, double, c, s);
    MRPT_LOAD_CONFIG_VAR(wall_height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(level_height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(levels, int, c, s);
    MRPT_LOAD_CONFIG_VAR(map_0, string, c, s);
    MRPT_LOAD_CONFIG_VAR(map_1, string, c, s);
    MRPT_LOAD_CONFIG_VAR(stairs_dir, string, c, s);
    MRPT_LOAD_CONFIG_VAR(door_probability, double, c, s);
    MRPT_LOAD_CONFIG_VAR(poster_probability, double, c, s);
    MRPT_LOAD_CONFIG_VAR(wall_texture, string, c, s);
    MRPT_LOAD_CONFIG_VAR(floor_texture, string, c, s);
    MRPT_LOAD_CONFIG_VAR(ceiling_texture, string, c, s);
    MRPT_LOAD_CONFIG_VAR(texel_size, double, c, s);
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
    MRPT_SAVE_CONFIG_VAR(cell_size, c, s);
    MRPT_SAVE_CONFIG_VAR(wall_height, c, s);
    MRPT_SAVE_CONFIG_VAR(level_height, c, s);
    MRPT_SAVE_CONFIG_VAR(levels, c, s);
    MRPT_SAVE_CONFIG_VAR(map_0, c, s);
    MRPT_SAVE_CONFIG_VAR(map_1, c, s);
    MRPT_SAVE_CONFIG_VAR(stairs_dir, c, s);
    MRPT_SAVE_CONFIG_VAR(door_probability, c, s);
    MRPT_SAVE_CONFIG_VAR(poster_probability, c, s);
    MRPT_SAVE_CONFIG_VAR(wall_texture, c, s);
    MRPT_SAVE_CONFIG_VAR(floor_texture, c, s);
    MRPT_SAVE_CONFIG_VAR(ceiling_texture, c, s);
    MRPT_SAVE_CONFIG_VAR(texel_size, c, s);
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
    MRPT_LOAD_CONFIG_VAR(extent, double, c, s);
    MRPT_LOAD_CONFIG_VAR(objects, int, c, s);
    MRPT_LOAD_CONFIG_VAR(min_size, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_size, double, c, s);
    MRPT_LOAD_CONFIG_VAR(clearance, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ground_texture, string, c, s);
    MRPT_LOAD_CONFIG_VAR(object_texture, string, c, s);
    MRPT_LOAD_CONFIG_VAR(texel_size, double, c, s);
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
    MRPT_SAVE_CONFIG_VAR(extent, c, s);
    MRPT_SAVE_CONFIG_VAR(objects, c, s);
    MRPT_SAVE_CONFIG_VAR(min_size, c, s);
    MRPT_SAVE_CONFIG_VAR(max_size, c, s);
    MRPT_SAVE_CONFIG_VAR(clearance, c, s);
    MRPT_SAVE_CONFIG_VAR(ground_texture, c, s);
    MRPT_SAVE_CONFIG_VAR(object_texture, c, s);
    MRPT_SAVE_CONFIG_VAR(texel_size, c, s);
}

void World::TTerrainParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    MRPT_LOAD_CONFIG_VAR(extent, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cell, double, c, s);
    MRPT_LOAD_CONFIG_VAR(amplitude, double, c, s);
    MRPT_LOAD_CONFIG_VAR(channel_depth, double, c, s);
    MRPT_LOAD_CONFIG_VAR(channel_width, double, c, s);
    MRPT_LOAD_CONFIG_VAR(rocks, int, c, s);
    MRPT_LOAD_CONFIG_VAR(bushes, int, c, s);
    MRPT_LOAD_CONFIG_VAR(clearance, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ground_texture, string, c, s);
    MRPT_LOAD_CONFIG_VAR(texel_size, double, c, s);
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
    MRPT_SAVE_CONFIG_VAR(extent, c, s);
    MRPT_SAVE_CONFIG_VAR(cell, c, s);
    MRPT_SAVE_CONFIG_VAR(amplitude, c, s);
    MRPT_SAVE_CONFIG_VAR(channel_depth, c, s);
    MRPT_SAVE_CONFIG_VAR(channel_width, c, s);
    MRPT_SAVE_CONFIG_VAR(rocks, c, s);
    MRPT_SAVE_CONFIG_VAR(bushes, c, s);
    MRPT_SAVE_CONFIG_VAR(clearance, c, s);
    MRPT_SAVE_CONFIG_VAR(ground_texture, c, s);
    MRPT_SAVE_CONFIG_VAR(texel_size, c, s);
}

// ---------------------------------------------------------------- World
std::size_t World::addElement(const Element& e)
{
    m_elements.push_back(e);
    return m_elements.size() - 1;
}

int World::addTexture(const ProceduralTexture& t)
{
    m_textures.push_back(t);
    return static_cast<int>(m_textures.size() - 1);
}

void World::setHeightField(const HeightField& h, int texture, double texel_size)
{
    m_height = h;
    const int B = HeightField::BLOCK;
    const int nbx = (h.heights.cols - 1 + B - 1) / B;
    const int nbz = (h.heights.rows - 1 + B - 1) / B;
    m_height.block_max.create(nbz, nbx, CV_32F);
    for (int bz = 0; bz < nbz; ++bz)
    {
        for (int bx = 0; bx < nbx; ++bx)
        {
            // The block's cells span samples [b*B, b*B + B] (inclusive) on each axis.
            const cv::Rect r(
                bx * B, bz * B, std::min(B + 1, h.heights.cols - bx * B),
                std::min(B + 1, h.heights.rows - bz * B));
            double mx = 0;
            cv::minMaxLoc(h.heights(r), nullptr, &mx);
            m_height.block_max.at<float>(bz, bx) = static_cast<float>(mx);
        }
    }
    const int C = HeightField::COARSE;
    const int ncx = (nbx + C - 1) / C;
    const int ncz = (nbz + C - 1) / C;
    m_height.coarse_max.create(ncz, ncx, CV_32F);
    for (int cz = 0; cz < ncz; ++cz)
    {
        for (int cx = 0; cx < ncx; ++cx)
        {
            const cv::Rect r(cx * C, cz * C, std::min(C, nbx - cx * C), std::min(C, nbz - cz * C));
            double mx = 0;
            cv::minMaxLoc(m_height.block_max(r), nullptr, &mx);
            m_height.coarse_max.at<float>(cz, cx) = static_cast<float>(mx);
        }
    }
    Element e;
    e.kind = Element::Kind::HeightField;
    e.lo = {h.x0, h.min_height, h.z0};
    e.hi = {
        h.x0 + h.cell * (h.heights.cols - 1), h.max_height, h.z0 + h.cell * (h.heights.rows - 1)};
    e.texture = texture;
    e.texel_size = texel_size;
    addElement(e);
}

double World::groundHeight(double x, double z) const
{
    return hasHeightField() ? m_height.at(x, z) : 0.0;
}

void World::load(
    const mrpt::config::CConfigFileBase& cfg, const std::vector<std::array<double, 2>>& keep_out)
{
    m_elements.clear();
    m_textures.clear();
    m_height = HeightField();
    if (!cfg.sectionExists("World"))
    {
        throw std::invalid_argument("[World]: section missing (it holds the world 'type')");
    }
    m_type = cfg.read_string("World", "type", "");
    const int seed = cfg.read_int("World", "seed", 1);
    const auto useed = static_cast<std::uint64_t>(seed);
    if (m_type == "building")
    {
        building.loadFromConfigFile(cfg, "Building");
        buildBuilding(cfg, useed);
    }
    else if (m_type == "ground")
    {
        ground.loadFromConfigFile(cfg, "Ground");
        buildGround(cfg, useed, keep_out);
    }
    else if (m_type == "terrain")
    {
        terrain.loadFromConfigFile(cfg, "Terrain");
        buildTerrain(cfg, useed, keep_out);
    }
    else if (m_type != "empty")
    {
        badKey(
            "World", "type",
            "unknown world type '" + m_type + "' (expected building, ground, terrain or empty)");
    }
    loadElements(cfg, useed);
    if (m_elements.empty())
    {
        throw std::invalid_argument("[World] type: the world '" + m_type + "' has no elements");
    }
}

void World::buildBuilding(const mrpt::config::CConfigFileBase&, std::uint64_t seed)
{
    const auto& p = building;
    std::vector<std::vector<std::string>> maps{splitRows(p.map_0)};
    if (p.levels == 2)
    {
        maps.push_back(splitRows(p.map_1));
    }
    for (std::size_t l = 0; l < maps.size(); ++l)
    {
        for (const auto& row : maps[l])
        {
            for (char ch : row)
            {
                if (ch != '#' && ch != '.' && ch != 'S')
                {
                    badKey(
                        "Building", "map_" + std::to_string(l),
                        std::string("unexpected character '") + ch + "' (use '#', '.', 'S', '/')");
                }
            }
        }
    }
    auto cellAt = [&](std::size_t l, int r, int c) -> char
    {
        if (r < 0 || c < 0 || r >= static_cast<int>(maps[l].size()) ||
            c >= static_cast<int>(maps[l][static_cast<std::size_t>(r)].size()))
        {
            return '#';
        }
        return maps[l][static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
    };
    auto solid = [&](std::size_t l, int r, int c) { return cellAt(l, r, c) == '#'; };

    std::mt19937_64 rng(mix(seed, 1));
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const int tex_size = 512;
    std::vector<int> wall_tex;
    for (int i = 0; i < 3; ++i)
    {
        wall_tex.push_back(
            addTexture(ProceduralTexture::generate(p.wall_texture, mix(seed, 100 + i), tex_size)));
    }
    const int floor_tex =
        addTexture(ProceduralTexture::generate(p.floor_texture, mix(seed, 200), tex_size));
    const int ceil_tex =
        addTexture(ProceduralTexture::generate(p.ceiling_texture, mix(seed, 300), tex_size));
    std::vector<int> door_tex;
    for (int i = 0; i < 3; ++i)
    {
        door_tex.push_back(
            addTexture(ProceduralTexture::generate("wood", mix(seed, 400 + i), 256)));
    }
    const int stairs_tex = addTexture(ProceduralTexture::generate("noise", mix(seed, 500), 256));

    const double cs = p.cell_size;
    const double tx = p.texel_size;
    int poster_count = 0;
    for (std::size_t l = 0; l < maps.size(); ++l)
    {
        const double base = static_cast<double>(l) * p.level_height;
        const double wall_top = base + (maps.size() > 1 && l == 0 ? p.level_height : p.wall_height);
        int rows = static_cast<int>(maps[l].size());
        int cols = 0;
        for (const auto& r : maps[l])
        {
            cols = std::max(cols, static_cast<int>(r.size()));
        }
        // Unit wall faces, keyed by (direction, boundary line) -> positions along it.
        std::map<std::pair<int, int>, std::vector<int>> faces;
        for (int r = 0; r < rows; ++r)
        {
            for (int c = 0; c < cols; ++c)
            {
                if (solid(l, r, c))
                {
                    continue;
                }
                if (solid(l, r, c + 1))
                {
                    faces[{0, c + 1}].push_back(r);
                }
                if (solid(l, r, c - 1))
                {
                    faces[{1, c}].push_back(r);
                }
                if (solid(l, r + 1, c))
                {
                    faces[{2, r + 1}].push_back(c);
                }
                if (solid(l, r - 1, c))
                {
                    faces[{3, r}].push_back(c);
                }
            }
        }
        for (auto& [key, pos] : faces)
        {
            const int dir = key.first;
            const double line = key.second * cs;
            std::sort(pos.begin(), pos.end());
            const int tex = wall_tex[static_cast<std::size_t>(key.second) % wall_tex.size()];
            std::size_t i = 0;
            while (i < pos.size())
            {
                std::size_t j = i;
                while (j + 1 < pos.size() && pos[j + 1] == pos[j] + 1)
                {
                    ++j;
                }
                const double a = pos[i] * cs;
                const double b = (pos[j] + 1) * cs;
                if (dir < 2)
                {
                    addElement(makePlane(0, {line, base, a}, {line, wall_top, b}, tex, tx));
                }
                else
                {
                    addElement(makePlane(2, {a, base, line}, {b, wall_top, line}, tex, tx));
                }
                i = j + 1;
            }
            // Doors and posters, one chance per unit face, 1 cm in front of the wall.
            const double inward = (dir == 0 || dir == 2) ? -0.01 : 0.01;
            for (int q : pos)
            {
                const double x = u01(rng);
                double w = 0;
                double h0 = 0;
                double h1 = 0;
                int tex_id = 0;
                bool add = false;
                if (x < p.door_probability)
                {
                    w = std::min(0.9, 0.8 * cs);
                    h0 = base;
                    h1 = base + std::min(2.0, 0.8 * p.wall_height);
                    tex_id = door_tex[static_cast<std::size_t>(q) % door_tex.size()];
                    add = true;
                }
                else if (x < p.door_probability + p.poster_probability)
                {
                    w = std::min(0.7, 0.6 * cs);
                    h0 = base + 0.45 * p.wall_height;
                    h1 = base + 0.75 * p.wall_height;
                    tex_id = addTexture(ProceduralTexture::generate(
                        "poster", mix(seed, 1000 + static_cast<std::uint64_t>(poster_count++)),
                        128));
                    add = true;
                }
                if (!add)
                {
                    continue;
                }
                const double mid = (q + 0.5) * cs;
                Element e;
                if (dir < 2)
                {
                    e = makePlane(
                        0, {line + inward, h0, mid - w / 2}, {line + inward, h1, mid + w / 2},
                        tex_id, tx);
                }
                else
                {
                    e = makePlane(
                        2, {mid - w / 2, h0, line + inward}, {mid + w / 2, h1, line + inward},
                        tex_id, tx);
                }
                e.stretch = true;
                addElement(e);
            }
        }
        // Floors and ceilings: runs of free cells per row (stairwell holes left open).
        for (int r = 0; r < rows; ++r)
        {
            for (int pass = 0; pass < 2; ++pass)
            {
                const bool is_floor = pass == 0;
                auto has = [&](int c)
                {
                    if (solid(l, r, c))
                    {
                        return false;
                    }
                    const bool stair = cellAt(0, r, c) == 'S';
                    if (is_floor)
                    {
                        return !(l > 0 && stair);
                    }
                    return !(l == 0 && stair && maps.size() > 1);
                };
                int c = 0;
                while (c < cols)
                {
                    if (!has(c))
                    {
                        ++c;
                        continue;
                    }
                    int e = c;
                    while (e + 1 < cols && has(e + 1))
                    {
                        ++e;
                    }
                    const double y = is_floor ? base : base + p.wall_height;
                    addElement(makePlane(
                        1, {c * cs, y, r * cs}, {(e + 1) * cs, y, (r + 1) * cs},
                        is_floor ? floor_tex : ceil_tex, tx));
                    c = e + 1;
                }
            }
        }
    }
    // Stairs: each 4-connected group of level-0 'S' cells is a staircase
    // rising to level 1 along its direction.
    if (maps.size() < 2)
    {
        return;
    }
    const std::vector<std::string> dirs = p.stairsDirections();
    std::vector<std::vector<bool>> seen(maps[0].size());
    for (std::size_t r = 0; r < maps[0].size(); ++r)
    {
        seen[r].assign(maps[0][r].size(), false);
    }
    std::size_t staircase = 0;
    for (int r = 0; r < static_cast<int>(maps[0].size()); ++r)
    {
        for (int c = 0; c < static_cast<int>(maps[0][static_cast<std::size_t>(r)].size()); ++c)
        {
            if (cellAt(0, r, c) != 'S' ||
                seen[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)])
            {
                continue;
            }
            // Flood fill: the bounding box of the group is the staircase.
            int r0 = r, r1 = r, c0 = c, c1 = c;
            std::vector<std::array<int, 2>> stack{{r, c}};
            seen[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] = true;
            while (!stack.empty())
            {
                const auto [cr, cc] = stack.back();
                stack.pop_back();
                r0 = std::min(r0, cr);
                r1 = std::max(r1, cr);
                c0 = std::min(c0, cc);
                c1 = std::max(c1, cc);
                const int nb[4][2] = {{cr + 1, cc}, {cr - 1, cc}, {cr, cc + 1}, {cr, cc - 1}};
                for (const auto& n : nb)
                {
                    if (cellAt(0, n[0], n[1]) == 'S' &&
                        !seen[static_cast<std::size_t>(n[0])][static_cast<std::size_t>(n[1])])
                    {
                        seen[static_cast<std::size_t>(n[0])][static_cast<std::size_t>(n[1])] = true;
                        stack.push_back({n[0], n[1]});
                    }
                }
            }
            if (dirs.size() > 1 && staircase >= dirs.size())
            {
                badKey(
                    "Building", "stairs_dir",
                    "map_0 has more staircases than the " + std::to_string(dirs.size()) +
                        " directions given");
            }
            const std::string& dir = dirs.size() == 1 ? dirs[0] : dirs[staircase];
            ++staircase;
            addStaircase(r0, r1, c0, c1, dir, stairs_tex);
        }
    }
    if (dirs.size() > 1 && staircase != dirs.size())
    {
        badKey(
            "Building", "stairs_dir",
            std::to_string(dirs.size()) + " directions given for " + std::to_string(staircase) +
                " staircases in map_0");
    }
}

void World::addStaircase(int r0, int r1, int c0, int c1, const std::string& dir, int texture)
{
    const auto& p = building;
    const double cs = p.cell_size;
    const double xa = c0 * cs;
    const double xb = (c1 + 1) * cs;
    const double za = r0 * cs;
    const double zb = (r1 + 1) * cs;
    const int n = std::max(2, static_cast<int>(std::lround(p.level_height / 0.18)));
    const bool along_x = dir[1] == 'x';
    const bool positive = dir[0] == '+';
    const double len = along_x ? xb - xa : zb - za;
    for (int k = 0; k < n; ++k)
    {
        const int kk = positive ? k : n - 1 - k;
        const double s0 = (along_x ? xa : za) + len * kk / n;
        const double s1 = s0 + len / n;
        const double top = p.level_height * (k + 1) / n;
        if (along_x)
        {
            addElement(makeBox({s0, 0, za}, {s1, top, zb}, texture, p.texel_size));
        }
        else
        {
            addElement(makeBox({xa, 0, s0}, {xb, top, s1}, texture, p.texel_size));
        }
    }
}

void World::buildGround(
    const mrpt::config::CConfigFileBase&,
    std::uint64_t seed,
    const std::vector<std::array<double, 2>>& keep_out)
{
    const auto& p = ground;
    const double h = p.extent / 2;
    const int gt = addTexture(ProceduralTexture::generate(p.ground_texture, mix(seed, 1), 512));
    addElement(makePlane(1, {-h, 0, -h}, {h, 0, h}, gt, p.texel_size));
    std::vector<int> obj_tex;
    for (int i = 0; i < 4; ++i)
    {
        obj_tex.push_back(
            addTexture(ProceduralTexture::generate(p.object_texture, mix(seed, 10 + i), 256)));
    }
    std::mt19937_64 rng(mix(seed, 2));
    std::uniform_real_distribution<double> pos(-0.95 * h, 0.95 * h);
    std::uniform_real_distribution<double> size(p.min_size, p.max_size);
    int placed = 0;
    for (int tries = 0; placed < p.objects && tries < 50 * (p.objects + 1); ++tries)
    {
        const double x = pos(rng);
        const double z = pos(rng);
        const double sx = size(rng);
        const double sz = size(rng);
        const double sy = size(rng);
        if (!keep_out.empty() &&
            distanceToPath(x, z, keep_out) < p.clearance + 0.5 * std::hypot(sx, sz))
        {
            continue;
        }
        addElement(makeBox(
            {x - sx / 2, 0, z - sz / 2}, {x + sx / 2, sy, z + sz / 2},
            obj_tex[static_cast<std::size_t>(placed) % obj_tex.size()], p.texel_size));
        ++placed;
    }
}

void World::buildTerrain(
    const mrpt::config::CConfigFileBase&,
    std::uint64_t seed,
    const std::vector<std::array<double, 2>>& keep_out)
{
    const auto& p = terrain;
    const int n = static_cast<int>(std::ceil(p.extent / p.cell)) + 1;
    HeightField hf;
    hf.cell = p.cell;
    hf.x0 = -p.extent / 2;
    hf.z0 = -p.extent / 2;
    // Relief: multi-scale noise, normalized to the requested amplitude.
    const ProceduralTexture relief = ProceduralTexture::generate("noise", mix(seed, 3), 256);
    cv::Mat h;
    cv::resize(relief.image(), h, cv::Size(n, n), 0, 0, cv::INTER_CUBIC);
    cv::Scalar mean;
    cv::Scalar stddev;
    cv::meanStdDev(h, mean, stddev);
    h = (h - mean[0]) * (p.amplitude / std::max(stddev[0], 1e-6));
    std::mt19937_64 rng(mix(seed, 4));
    std::uniform_real_distribution<double> pos(-0.45 * p.extent, 0.45 * p.extent);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    struct Bump
    {
        double x, z, r, a;
    };
    std::vector<Bump> bumps;
    for (int tries = 0; static_cast<int>(bumps.size()) < p.rocks && tries < 50 * (p.rocks + 1);
         ++tries)
    {
        const Bump b{pos(rng), pos(rng), 0.2 + 0.5 * u01(rng), 0.1 + 0.4 * u01(rng)};
        if (!keep_out.empty() && distanceToPath(b.x, b.z, keep_out) < p.clearance + 2 * b.r)
        {
            continue;
        }
        bumps.push_back(b);
    }
    for (int iz = 0; iz < n; ++iz)
    {
        const double z = hf.z0 + iz * p.cell;
        const double centre = 3.0 * std::sin(z / 7.0);
        for (int ix = 0; ix < n; ++ix)
        {
            const double x = hf.x0 + ix * p.cell;
            const double d = (x - centre) / (0.5 * p.channel_width);
            double v = h.at<float>(iz, ix) - p.channel_depth * std::exp(-d * d);
            for (const auto& b : bumps)
            {
                const double r2 = ((x - b.x) * (x - b.x) + (z - b.z) * (z - b.z)) / (b.r * b.r);
                if (r2 < 9)
                {
                    v += b.a * std::exp(-r2);
                }
            }
            h.at<float>(iz, ix) = static_cast<float>(v);
        }
    }
    hf.heights = h;
    double mn = 0;
    double mx = 0;
    cv::minMaxLoc(h, &mn, &mx);
    hf.min_height = static_cast<float>(mn);
    hf.max_height = static_cast<float>(mx);
    // Slope bound and Lambert shading (light from above and the side).
    cv::Mat gx;
    cv::Mat gz;
    cv::Sobel(h, gx, CV_32F, 1, 0, 1, 0.5 / p.cell);
    cv::Sobel(h, gz, CV_32F, 0, 1, 1, 0.5 / p.cell);
    double sx = 0;
    double sz = 0;
    cv::minMaxLoc(cv::abs(gx), nullptr, &sx);
    cv::minMaxLoc(cv::abs(gz), nullptr, &sz);
    hf.max_slope = std::max({sx, sz, 0.05});
    hf.shade.create(n, n, CV_32F);
    const double lx = 0.5;
    const double ly = 0.8;
    const double lz = 0.33;
    for (int iz = 0; iz < n; ++iz)
    {
        for (int ix = 0; ix < n; ++ix)
        {
            const double ax = -gx.at<float>(iz, ix);
            const double az = -gz.at<float>(iz, ix);
            const double norm = std::sqrt(ax * ax + 1 + az * az);
            const double lam =
                (ax * lx + ly + az * lz) / norm / std::sqrt(lx * lx + ly * ly + lz * lz);
            hf.shade.at<float>(iz, ix) = static_cast<float>(0.35 + 0.65 * std::max(0.0, lam));
        }
    }
    const int gt = addTexture(ProceduralTexture::generate(p.ground_texture, mix(seed, 5), 512));
    setHeightField(hf, gt, p.texel_size);
    // Bushes: boxes standing on the relief.
    const int bush_tex = addTexture(ProceduralTexture::generate("bush", mix(seed, 6), 256));
    int placed = 0;
    for (int tries = 0; placed < p.bushes && tries < 50 * (p.bushes + 1); ++tries)
    {
        const double x = pos(rng);
        const double z = pos(rng);
        const double s = 0.4 + 0.8 * u01(rng);
        const double t = 0.3 + 0.7 * u01(rng);
        if (!keep_out.empty() && distanceToPath(x, z, keep_out) < p.clearance + s)
        {
            continue;
        }
        const double g = m_height.at(x, z);
        addElement(makeBox(
            {x - s / 2, g - 0.1, z - s / 2}, {x + s / 2, g + t, z + s / 2}, bush_tex, 0.01));
        ++placed;
    }
}

void World::loadElements(const mrpt::config::CConfigFileBase& cfg, std::uint64_t seed)
{
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    std::uint64_t k = 0;
    for (const auto& s : sections)
    {
        if (s.rfind("Element", 0) != 0)
        {
            continue;
        }
        ++k;
        const std::string type = cfg.read_string(s, "type", "");
        const std::string tex = cfg.read_string(s, "texture", "noise");
        requireTexture(tex, s, "texture");
        const double texel = readNumber(cfg, s, "texel_size", 0.01);
        requireRange(texel, 1e-6, 1e3, s, "texel_size");
        const Vec3 lo = readVec3(cfg, s, "min");
        const Vec3 hi = readVec3(cfg, s, "max");
        for (int a = 0; a < 3; ++a)
        {
            if (hi[static_cast<std::size_t>(a)] < lo[static_cast<std::size_t>(a)])
            {
                badKey(s, "max", "every coordinate must be >= the one of 'min'");
            }
        }
        const int tid = addTexture(ProceduralTexture::generate(tex, mix(seed, 5000 + k), 256));
        Element e;
        if (type == "plane")
        {
            int axis = -1;
            int flat = 0;
            for (int a = 0; a < 3; ++a)
            {
                if (lo[static_cast<std::size_t>(a)] == hi[static_cast<std::size_t>(a)])
                {
                    axis = a;
                    ++flat;
                }
            }
            if (flat != 1)
            {
                badKey(s, "min", "a plane needs exactly one coordinate with min == max");
            }
            e = makePlane(axis, lo, hi, tid, texel);
            e.stretch = cfg.read_bool(s, "stretch", false);
        }
        else if (type == "box" || type == "moving_box")
        {
            e = makeBox(lo, hi, tid, texel);
            if (type == "moving_box")
            {
                e.velocity = readVec3(cfg, s, "velocity");
                e.t0 = readNumber(cfg, s, "t0", 0.0);
                requireRange(e.t0, -1e10, 1e10, s, "t0");
            }
        }
        else
        {
            badKey(
                s, "type",
                "unknown element type '" + type + "' (expected plane, box or moving_box)");
        }
        addElement(e);
    }
}

}  // namespace emslam::sim
