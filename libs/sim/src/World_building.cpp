// SPDX-License-Identifier: BSD-3-Clause
// World generator for type = building: walls, doors, posters, floors,
// ceilings and staircases from the [Building] floor plans.
#include "WorldDetail.h"

#include <emslam/sim/World.h>

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

namespace emslam::sim
{
using detail::badKey;
using detail::makeBox;
using detail::makePlane;
using detail::mix;

namespace
{
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

/** The floor plans, one per level, as rows of cells; outside is solid. */
struct FloorPlans
{
    std::vector<std::vector<std::string>> maps;

    char cellAt(std::size_t l, int r, int c) const
    {
        if (r < 0 || c < 0 || r >= static_cast<int>(maps[l].size()) ||
            c >= static_cast<int>(maps[l][static_cast<std::size_t>(r)].size()))
        {
            return '#';
        }
        return maps[l][static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
    }
    bool solid(std::size_t l, int r, int c) const { return cellAt(l, r, c) == '#'; }
};

FloorPlans loadFloorPlans(const World::TBuildingParams& p)
{
    FloorPlans plans{{splitRows(p.map_0)}};
    if (p.levels == 2)
    {
        plans.maps.push_back(splitRows(p.map_1));
    }
    for (std::size_t l = 0; l < plans.maps.size(); ++l)
    {
        for (const auto& row : plans.maps[l])
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
    return plans;
}

struct BuildingTextures
{
    std::vector<int> wall;
    int floor{0};
    int ceiling{0};
    std::vector<int> door;
    int stairs{0};
};

BuildingTextures addBuildingTextures(World& w, const World::TBuildingParams& p, std::uint64_t seed)
{
    const int tex_size = 512;
    BuildingTextures t;
    for (int i = 0; i < 3; ++i)
    {
        t.wall.push_back(w.addTexture(
            ProceduralTexture::generate(p.wall_texture, mix(seed, 100 + i), tex_size)));
    }
    t.floor = w.addTexture(ProceduralTexture::generate(p.floor_texture, mix(seed, 200), tex_size));
    t.ceiling =
        w.addTexture(ProceduralTexture::generate(p.ceiling_texture, mix(seed, 300), tex_size));
    for (int i = 0; i < 3; ++i)
    {
        t.door.push_back(
            w.addTexture(ProceduralTexture::generate("wood", mix(seed, 400 + i), 256)));
    }
    t.stairs = w.addTexture(ProceduralTexture::generate("noise", mix(seed, 500), 256));
    return t;
}

/** Unit wall faces of level l, keyed by (direction, boundary line) ->
 * positions along it. */
std::map<std::pair<int, int>, std::vector<int>> wallFaces(
    const FloorPlans& plans, std::size_t l, int rows, int cols)
{
    std::map<std::pair<int, int>, std::vector<int>> faces;
    for (int r = 0; r < rows; ++r)
    {
        for (int c = 0; c < cols; ++c)
        {
            if (plans.solid(l, r, c))
            {
                continue;
            }
            if (plans.solid(l, r, c + 1))
            {
                faces[{0, c + 1}].push_back(r);
            }
            if (plans.solid(l, r, c - 1))
            {
                faces[{1, c}].push_back(r);
            }
            if (plans.solid(l, r + 1, c))
            {
                faces[{2, r + 1}].push_back(c);
            }
            if (plans.solid(l, r - 1, c))
            {
                faces[{3, r}].push_back(c);
            }
        }
    }
    return faces;
}

/** One level of the building: its heights and what draws doors and posters. */
struct LevelContext
{
    World& world;
    const World::TBuildingParams& p;
    const BuildingTextures& tex;
    std::uint64_t seed;
    std::mt19937_64& rng;
    std::uniform_real_distribution<double>& u01;
    int& poster_count;
    double base;
    double wall_top;
};

/** One wall plane per run of consecutive unit faces along a line. */
void addWallRuns(const LevelContext& L, int dir, double line, const std::vector<int>& pos, int tex)
{
    const double cs = L.p.cell_size;
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
            L.world.addElement(
                makePlane(0, {line, L.base, a}, {line, L.wall_top, b}, tex, L.p.texel_size));
        }
        else
        {
            L.world.addElement(
                makePlane(2, {a, L.base, line}, {b, L.wall_top, line}, tex, L.p.texel_size));
        }
        i = j + 1;
    }
}

/** Doors and posters, one chance per unit face, 1 cm in front of the wall. */
void addDoorsAndPosters(const LevelContext& L, int dir, double line, const std::vector<int>& pos)
{
    const auto& p = L.p;
    const double cs = p.cell_size;
    const double inward = (dir == 0 || dir == 2) ? -0.01 : 0.01;
    for (int q : pos)
    {
        const double x = L.u01(L.rng);
        double w = 0;
        double h0 = 0;
        double h1 = 0;
        int tex_id = 0;
        if (x < p.door_probability)
        {
            w = std::min(0.9, 0.8 * cs);
            h0 = L.base;
            h1 = L.base + std::min(2.0, 0.8 * p.wall_height);
            tex_id = L.tex.door[static_cast<std::size_t>(q) % L.tex.door.size()];
        }
        else if (x < p.door_probability + p.poster_probability)
        {
            w = std::min(0.7, 0.6 * cs);
            h0 = L.base + 0.45 * p.wall_height;
            h1 = L.base + 0.75 * p.wall_height;
            tex_id = L.world.addTexture(ProceduralTexture::generate(
                "poster", mix(L.seed, 1000 + static_cast<std::uint64_t>(L.poster_count++)), 128));
        }
        else
        {
            continue;
        }
        const double mid = (q + 0.5) * cs;
        Element e;
        if (dir < 2)
        {
            e = makePlane(
                0, {line + inward, h0, mid - w / 2}, {line + inward, h1, mid + w / 2}, tex_id,
                p.texel_size);
        }
        else
        {
            e = makePlane(
                2, {mid - w / 2, h0, line + inward}, {mid + w / 2, h1, line + inward}, tex_id,
                p.texel_size);
        }
        e.stretch = true;
        L.world.addElement(e);
    }
}

/** Floors and ceilings of level l: runs of free cells per row (stairwell
 * holes left open). */
void addFloorsAndCeilings(
    const LevelContext& L, const FloorPlans& plans, std::size_t l, int rows, int cols)
{
    const double cs = L.p.cell_size;
    for (int r = 0; r < rows; ++r)
    {
        for (int pass = 0; pass < 2; ++pass)
        {
            const bool is_floor = pass == 0;
            auto has = [&](int c)
            {
                if (plans.solid(l, r, c))
                {
                    return false;
                }
                const bool stair = plans.cellAt(0, r, c) == 'S';
                if (is_floor)
                {
                    return !(l > 0 && stair);
                }
                return !(l == 0 && stair && plans.maps.size() > 1);
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
                const double y = is_floor ? L.base : L.base + L.p.wall_height;
                L.world.addElement(makePlane(
                    1, {c * cs, y, r * cs}, {(e + 1) * cs, y, (r + 1) * cs},
                    is_floor ? L.tex.floor : L.tex.ceiling, L.p.texel_size));
                c = e + 1;
            }
        }
    }
}

/** Bounding box (rows r0..r1, columns c0..c1) of a group of cells. */
struct CellBox
{
    int r0, r1, c0, c1;
};

/** Each 4-connected group of level-0 'S' cells, in row-major order of
 * their first cell: its bounding box is a staircase. */
std::vector<CellBox> stairGroups(const FloorPlans& plans)
{
    const auto& map = plans.maps[0];
    std::vector<std::vector<bool>> seen(map.size());
    for (std::size_t r = 0; r < map.size(); ++r)
    {
        seen[r].assign(map[r].size(), false);
    }
    const auto mark = [&](int r, int c)
    {
        if (plans.cellAt(0, r, c) != 'S')
        {
            return false;  // also every cell outside the plan
        }
        auto&& s = seen[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
        if (s)
        {
            return false;
        }
        s = true;
        return true;
    };
    std::vector<CellBox> groups;
    for (int r = 0; r < static_cast<int>(map.size()); ++r)
    {
        for (int c = 0; c < static_cast<int>(map[static_cast<std::size_t>(r)].size()); ++c)
        {
            if (!mark(r, c))
            {
                continue;
            }
            // Flood fill: the bounding box of the group is the staircase.
            CellBox b{r, r, c, c};
            std::vector<std::array<int, 2>> stack{{r, c}};
            while (!stack.empty())
            {
                const auto [cr, cc] = stack.back();
                stack.pop_back();
                b.r0 = std::min(b.r0, cr);
                b.r1 = std::max(b.r1, cr);
                b.c0 = std::min(b.c0, cc);
                b.c1 = std::max(b.c1, cc);
                const int nb[4][2] = {{cr + 1, cc}, {cr - 1, cc}, {cr, cc + 1}, {cr, cc - 1}};
                for (const auto& n : nb)
                {
                    if (mark(n[0], n[1]))
                    {
                        stack.push_back({n[0], n[1]});
                    }
                }
            }
            groups.push_back(b);
        }
    }
    return groups;
}
}  // namespace

void World::buildBuilding(const mrpt::config::CConfigFileBase&, std::uint64_t seed)
{
    const auto& p = building;
    const FloorPlans plans = loadFloorPlans(p);
    const auto& maps = plans.maps;
    std::mt19937_64 rng(mix(seed, 1));
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const BuildingTextures tex = addBuildingTextures(*this, p, seed);
    int poster_count = 0;
    for (std::size_t l = 0; l < maps.size(); ++l)
    {
        const double base = static_cast<double>(l) * p.level_height;
        const double wall_top = base + (maps.size() > 1 && l == 0 ? p.level_height : p.wall_height);
        const LevelContext level{*this, p, tex, seed, rng, u01, poster_count, base, wall_top};
        const int rows = static_cast<int>(maps[l].size());
        int cols = 0;
        for (const auto& r : maps[l])
        {
            cols = std::max(cols, static_cast<int>(r.size()));
        }
        for (auto& [key, pos] : wallFaces(plans, l, rows, cols))
        {
            std::sort(pos.begin(), pos.end());
            const double line = key.second * p.cell_size;
            addWallRuns(
                level, key.first, line, pos,
                tex.wall[static_cast<std::size_t>(key.second) % tex.wall.size()]);
            addDoorsAndPosters(level, key.first, line, pos);
        }
        addFloorsAndCeilings(level, plans, l, rows, cols);
    }
    // Stairs: each staircase rises to level 1 along its direction.
    if (maps.size() < 2)
    {
        return;
    }
    const std::vector<std::string> dirs = p.stairsDirections();
    std::size_t staircase = 0;
    for (const CellBox& b : stairGroups(plans))
    {
        if (dirs.size() > 1 && staircase >= dirs.size())
        {
            badKey(
                "Building", "stairs_dir",
                "map_0 has more staircases than the " + std::to_string(dirs.size()) +
                    " directions given");
        }
        const std::string& dir = dirs.size() == 1 ? dirs[0] : dirs[staircase];
        ++staircase;
        addStaircase(b.r0, b.r1, b.c0, b.c1, dir, tex.stairs);
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

}  // namespace emslam::sim
