// SPDX-License-Identifier: BSD-3-Clause
#include "SimTestWorlds.h"
#include "TestHelpers.h"

#include <emslam/sim/World.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

using emslam::sim::Element;
using emslam::sim::World;

namespace
{
World loadWorld(const std::string& text)
{
    mrpt::config::CConfigFileMemory cfg(text);
    World w;
    w.load(cfg);
    return w;
}
}  // namespace

TEST(World, buildingHasMergedWallsFloorsAndCeilings)
{
    // One 1 x 3 corridor: 4 merged walls, 1 floor strip per row (3), 3 ceilings.
    const World w = loadWorld(
        "[World]\ntype = building\n[Building]\ncell_size = 2\nwall_height = 2.5\n"
        "door_probability = 0\nposter_probability = 0\nmap_0 = ###/#.#/#.#/#.#/###\n");
    int walls = 0;
    int floors = 0;
    int ceilings = 0;
    for (const Element& e : w.elements())
    {
        ASSERT_EQ(e.kind, Element::Kind::Plane);
        if (e.axis == 1)
        {
            (e.lo[1] == 0.0 ? floors : ceilings)++;
            EXPECT_TRUE(e.lo[1] == 0.0 || e.lo[1] == 2.5);
        }
        else
        {
            ++walls;
            EXPECT_EQ(e.lo[1], 0.0);
            EXPECT_EQ(e.hi[1], 2.5);
        }
    }
    EXPECT_EQ(walls, 4);
    EXPECT_EQ(floors, 3);
    EXPECT_EQ(ceilings, 3);
}

TEST(World, twoLevelBuildingHasStairs)
{
    const World w = loadWorld(
        "[World]\ntype = building\n[Building]\nlevels = 2\nlevel_height = 3.0\n"
        "map_0 = #####/#.SS#/#####\nmap_1 = #####/#.SS#/#####\n");
    int boxes = 0;
    double top = 0;
    for (const Element& e : w.elements())
    {
        if (e.kind == Element::Kind::Box)
        {
            ++boxes;
            top = std::max(top, e.hi[1]);
        }
    }
    EXPECT_GT(boxes, 10);
    EXPECT_DOUBLE_EQ(top, 3.0);
}

TEST(World, eachGroupOfStairCellsIsAStaircaseWithItsOwnDirection)
{
    // Two 2-cell staircases (rows 1 and 3), the first rising along +x, the
    // second along -x: each spans only its own cells.
    const std::string plan = "######/#.SS.#/######/#.SS.#/######";
    const World w = loadWorld(
        "[World]\ntype = building\n[Building]\nlevels = 2\nlevel_height = 3.0\n"
        "cell_size = 2\nstairs_dir = +x -x\nmap_0 = " +
        plan + "\nmap_1 = " + plan + "\n");
    std::vector<const Element*> row1, row3;
    for (const Element& e : w.elements())
    {
        if (e.kind == Element::Kind::Box)
        {
            ASSERT_TRUE(e.lo[2] == 2.0 || e.lo[2] == 6.0) << e.lo[2];
            (e.lo[2] == 2.0 ? row1 : row3).push_back(&e);
            EXPECT_DOUBLE_EQ(e.hi[2] - e.lo[2], 2.0);
            EXPECT_GE(e.lo[0], 4.0);
            EXPECT_LE(e.hi[0], 8.0);
        }
    }
    ASSERT_EQ(row1.size(), row3.size());
    ASSERT_GT(row1.size(), 10U);
    // The highest step is at the +x end of the first and the -x end of the second.
    auto highest = [](const std::vector<const Element*>& v)
    {
        return *std::max_element(
            v.begin(), v.end(), [](auto a, auto b) { return a->hi[1] < b->hi[1]; });
    };
    EXPECT_DOUBLE_EQ(highest(row1)->hi[1], 3.0);
    EXPECT_DOUBLE_EQ(highest(row1)->hi[0], 8.0);
    EXPECT_DOUBLE_EQ(highest(row3)->hi[1], 3.0);
    EXPECT_DOUBLE_EQ(highest(row3)->lo[0], 4.0);

    const auto withDirections = [&](const std::string& dirs)
    {
        loadWorld(
            "[World]\ntype = building\n[Building]\nlevels = 2\nstairs_dir = " + dirs +
            "\nmap_0 = " + plan + "\nmap_1 = " + plan + "\n");
    };
    emslam::test::expectThrowContaining(
        [&] { withDirections("+x -x +z"); },
        {"[Building] stairs_dir", "3 directions given for 2 staircases"});
    emslam::test::expectThrowContaining(
        [&] { withDirections("+x up"); }, {"[Building] stairs_dir", "+x up"});
}

TEST(World, terrainHeightFieldAndGroundObjectsKeepThePathFree)
{
    const std::vector<std::array<double, 2>> path{{-5, 0}, {5, 0}};
    mrpt::config::CConfigFileMemory t(
        "[World]\ntype = terrain\n[Terrain]\nextent = 20\ncell = 0.2\nrocks = 30\nbushes = 20\n"
        "clearance = 1.5\n");
    World w;
    w.load(t, path);
    ASSERT_TRUE(w.hasHeightField());
    EXPECT_NE(w.groundHeight(1.0, 2.0), 0.0);
    mrpt::config::CConfigFileMemory g(
        "[World]\ntype = ground\n[Ground]\nobjects = 50\nclearance = 1.5\n");
    World wg;
    wg.load(g, path);
    for (const Element& e : wg.elements())
    {
        if (e.kind == Element::Kind::Box)
        {
            const bool overlaps_path =
                e.lo[2] < 1.5 && e.hi[2] > -1.5 && e.lo[0] < 5.0 && e.hi[0] > -5.0;
            EXPECT_FALSE(overlaps_path);
        }
    }
}

TEST(World, explicitElements)
{
    const World w = loadWorld(
        "[World]\ntype = empty\n[Element_wall]\ntype = plane\nmin = -1 -1 4\nmax = 1 1 4\n"
        "[Element_mover]\ntype = moving_box\nmin = 0 0 2\nmax = 1 1 3\nvelocity = 1 0 0\n");
    ASSERT_EQ(w.elements().size(), 2U);
    int planes = 0;
    int movers = 0;
    for (const Element& e : w.elements())
    {
        if (e.kind == Element::Kind::Plane)
        {
            ++planes;
            EXPECT_EQ(e.axis, 2);
        }
        else
        {
            movers += e.moving() ? 1 : 0;
        }
    }
    EXPECT_EQ(planes, 1);
    EXPECT_EQ(movers, 1);
}

TEST(World, badIniNamesTheKey)
{
    using emslam::test::expectThrowContaining;
    expectThrowContaining(
        [] { loadWorld("[World]\ntype = castle\n"); }, {"[World] type", "castle"});
    expectThrowContaining(
        []
        { loadWorld("[World]\ntype = empty\n[Element_a]\ntype = sphere\nmin=0 0 0\nmax=1 1 1\n"); },
        {"[Element_a] type", "sphere"});
    expectThrowContaining(
        [] { loadWorld("[World]\ntype = empty\n[Element_a]\ntype = box\nmin=0 0\nmax=1 1 1\n"); },
        {"[Element_a] min"});
    expectThrowContaining(
        [] { loadWorld("[World]\ntype = building\n[Building]\nmap_0 = #x#\n"); },
        {"[Building] map_0", "x"});
    expectThrowContaining(
        [] { loadWorld("[World]\ntype = building\n[Building]\ncell_size = -2\nmap_0 = #.#\n"); },
        {"[Building] cell_size"});
    expectThrowContaining(
        [] { loadWorld("[World]\ntype = ground\n[Ground]\nground_texture = lava\n"); },
        {"[Ground] ground_texture", "lava"});
    expectThrowContaining([] { loadWorld("[Other]\na = 1\n"); }, {"[World]"});
}

TEST(World, parametersSaveLoadRoundTrip)
{
    World::TBuildingParams b;
    b.cell_size = 2.5;
    b.levels = 2;
    b.map_0 = "###/#S#/###";
    b.map_1 = "###/#S#/###";
    b.stairs_dir = "-z";
    b.wall_texture = "bricks";
    mrpt::config::CConfigFileMemory c;
    b.saveToConfigFile(c, "Building");
    mrpt::config::CConfigFileMemory reparsed(c.getContent());
    World::TBuildingParams b2;
    b2.loadFromConfigFile(reparsed, "Building");
    EXPECT_EQ(b2.cell_size, 2.5);
    EXPECT_EQ(b2.levels, 2);
    EXPECT_EQ(b2.map_1, b.map_1);
    EXPECT_EQ(b2.stairs_dir, "-z");
    EXPECT_EQ(b2.wall_texture, "bricks");

    World::TTerrainParams t;
    t.rocks = 7;
    t.amplitude = 0.4;
    mrpt::config::CConfigFileMemory c2;
    t.saveToConfigFile(c2, "Terrain");
    mrpt::config::CConfigFileMemory r2(c2.getContent());
    World::TTerrainParams t2;
    t2.loadFromConfigFile(r2, "Terrain");
    EXPECT_EQ(t2.rocks, 7);
    EXPECT_EQ(t2.amplitude, 0.4);
}
