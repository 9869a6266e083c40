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
}  // namespace

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

}  // namespace emslam::sim
