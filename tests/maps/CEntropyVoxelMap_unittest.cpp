// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/maps/registerAllClasses.h>

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CSetOfTriangles.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <gtest/gtest.h>

#include <TestData.h>
#include <TestHelpers.h>

#include <cmath>
#include <random>

using emslam::CEntropyVoxelMap;
using emslam::maps::EnergyType;
using emslam::maps::EntropyTerm;
using emslam::maps::WeightedPointCloud;
using mrpt::poses::CPose3D;

namespace
{
constexpr double DEG = M_PI / 180.0;

/** A Manhattan room in the optical frame (y down): floor, ceiling and four
 * walls sampled every `step` m with jitter; planes lie at cell centres of a
 * 0.15 m grid so that the aligned room is crisp. */
WeightedPointCloud makeRoom(unsigned seed, double step = 0.05)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jit(-0.01, 0.01);
    WeightedPointCloud c;
    const double X = 3.075, Y0 = -1.575, Y1 = 1.425, Z = 4.125;
    const auto add = [&](double x, double y, double z)
    {
        c.push_back(
            mrpt::math::TPoint3Df(
                static_cast<float>(x + jit(rng) * 0.3), static_cast<float>(y + jit(rng) * 0.3),
                static_cast<float>(z + jit(rng) * 0.3)),
            1.0f);
    };
    for (double a = -X; a <= X; a += step)
    {
        for (double b = -Z; b <= Z; b += step)
        {
            add(a + jit(rng), Y1, b + jit(rng));  // floor
            add(a + jit(rng), Y0, b + jit(rng));  // ceiling
        }
    }
    for (double y = Y0; y <= Y1; y += step)
    {
        for (double b = -Z; b <= Z; b += step)
        {
            add(-X, y + jit(rng), b + jit(rng));
            add(X, y + jit(rng), b + jit(rng));
        }
        for (double a = -X; a <= X; a += step)
        {
            add(a + jit(rng), y + jit(rng), -Z);
            add(a + jit(rng), y + jit(rng), Z);
        }
    }
    return c;
}

CEntropyVoxelMap::TCreationOptions creation(EnergyType e, double cell = 0.15)
{
    CEntropyVoxelMap::TCreationOptions o;
    o.cell_size = cell;
    o.energy = e;
    o.dof = emslam::maps::energyDof(e);
    return o;
}

void expectTrackedEqualsScratch(const CEntropyVoxelMap& m, const std::string& what)
{
    const auto scratch = m.computeEntropiesFromScratch();
    for (std::size_t t = 0; t < emslam::maps::NUM_ENTROPY_TERMS; t++)
    {
        if (const auto* h = m.trackedHistogram(static_cast<EntropyTerm>(t)))
        {
            EXPECT_NEAR(h->entropy(), scratch[t], 1e-9)
                << what << " term " << emslam::maps::toString(static_cast<EntropyTerm>(t));
        }
    }
    EXPECT_NEAR(
        m.energy(), emslam::maps::energyFromTerms(m.creationOptions().energy, scratch), 1e-9)
        << what;
}

const char* INI_TEXT = R"ini(
[Map]
entropyVoxelMap_count = 1

[Map_entropyVoxelMap_00_creationOpts]
cell_size = 0.35
energy    = planar_structured
dof       = 3

[Map_entropyVoxelMap_00_insertOpts]
max_range  = 12.5
min_range  = 0.2
decimation = 2

[Map_entropyVoxelMap_00_drawOpts]
max_cubes     = 1234
min_cube_size = 0.3
)ini";

mrpt::obs::CObservationPointCloud::Ptr pointCloudObs(const WeightedPointCloud& c)
{
    auto pts = mrpt::maps::CSimplePointsMap::Create();
    for (const auto& p : c.points)
    {
        pts->insertPoint(p.x, p.y, p.z);
    }
    auto obs = mrpt::obs::CObservationPointCloud::Create();
    obs->pointcloud = pts;
    return obs;
}
}  // namespace

TEST(CEntropyVoxelMap, alignedManhattanRoomHasLowestStructuredEnergy)
{
    CEntropyVoxelMap m(creation(EnergyType::Structured));
    m.insertWeightedCloud(makeRoom(1), CPose3D());
    const double e0 = m.energy();
    const double h0 = m.entropy(EntropyTerm::H3D);
    double prev = e0;
    for (double deg : {2.0, 5.0, 10.0})
    {
        // Rotation about the vertical axis (optical Y = MRPT's pitch angle).
        const double e = m.moveObservation(0, CPose3D(0, 0, 0, 0, deg * DEG, 0));
        EXPECT_GT(e, e0 + 0.05) << deg << " deg";
        EXPECT_GT(e, prev) << deg << " deg";
        prev = e;
        m.revertLastMove();
        EXPECT_NEAR(m.energy(), e0, 1e-9);
    }
    EXPECT_NEAR(m.entropy(EntropyTerm::H3D), h0, 1e-9);
}

TEST(CEntropyVoxelMap, misalignedSecondViewRaisesEntropy)
{
    CEntropyVoxelMap m(creation(EnergyType::Unstructured));
    m.insertWeightedCloud(makeRoom(1, 0.07), CPose3D());
    m.insertWeightedCloud(makeRoom(2, 0.07), CPose3D());
    const double aligned = m.entropy(EntropyTerm::H3D);
    m.moveObservation(1, CPose3D(0.3, 0.05, -0.2, 5 * DEG, 2 * DEG, 0));
    EXPECT_GT(m.entropy(EntropyTerm::H3D), aligned + 0.1);
    EXPECT_NEAR(m.energy(), m.entropy(EntropyTerm::H3D), 1e-12);  // Exp. 8
}

TEST(CEntropyVoxelMap, incrementalMovesEqualFromScratchForEveryEnergy)
{
    for (int e = 0; e <= static_cast<int>(EnergyType::PlanarStructured); e++)
    {
        const auto energy = static_cast<EnergyType>(e);
        CEntropyVoxelMap m(creation(energy));
        std::mt19937 rng(100 + e);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        const auto room = makeRoom(3, 0.1);
        for (int i = 0; i < 6; i++)
        {
            // Pieces of the room, each in its own frame.
            WeightedPointCloud piece;
            for (std::size_t j = i; j < room.size(); j += 6)
            {
                piece.push_back(room.points[j], static_cast<float>(1 + (j % 5)));
            }
            m.insertWeightedCloud(
                piece, CPose3D(0.2 * u(rng), 0.1 * u(rng), 0.3 * u(rng), 0, 0, 0));
        }
        expectTrackedEqualsScratch(m, "after insertion, " + emslam::maps::toString(energy));
        for (int it = 0; it < 400; it++)
        {
            std::vector<CEntropyVoxelMap::ObservationMove> moves;
            const int k = 1 + static_cast<int>(rng() % 3);
            for (int j = 0; j < k; j++)
            {
                const std::size_t idx = rng() % m.observationCount();
                const CPose3D d(
                    0.05 * u(rng), 0.05 * u(rng), 0.05 * u(rng), 3 * DEG * u(rng), 3 * DEG * u(rng),
                    3 * DEG * u(rng));
                moves.push_back({idx, m.observationPose(idx) + d});
            }
            const double before = m.energy();
            const double after = m.moveObservations(moves);
            if (rng() % 2 == 0)
            {
                EXPECT_NEAR(m.revertLastMove(), before, 1e-9);
                EXPECT_FALSE(m.canRevert());
            }
            else
            {
                EXPECT_DOUBLE_EQ(after, m.energy());
            }
            if (it % 50 == 0)
            {
                expectTrackedEqualsScratch(m, "iteration " + std::to_string(it));
            }
        }
        expectTrackedEqualsScratch(m, "end, " + emslam::maps::toString(energy));
        const double inc = m.energy();
        EXPECT_NEAR(m.recomputeFromScratch(), inc, 1e-9);
    }
}

// Two paths the random moves above reach only by chance: a move into empty
// space makes every histogram grow (their undo records are then cancelled
// and the map undoes the move by re-applying it), and a move list naming
// an observation twice (applied one move at a time, the last pose wins).
TEST(CEntropyVoxelMap, growingMovesAndRepeatedIndicesAreHandled)
{
    for (int e = 0; e <= static_cast<int>(EnergyType::PlanarStructured); e++)
    {
        const auto energy = static_cast<EnergyType>(e);
        const std::string name = emslam::maps::toString(energy);
        CEntropyVoxelMap m(creation(energy));
        const auto room = makeRoom(5, 0.1);
        m.insertWeightedCloud(room, CPose3D());
        m.insertWeightedCloud(room, CPose3D(0.1, 0, 0.2, 0, 0, 0));
        const double before = m.energy();

        // Far away: all of its cells are new.
        m.moveObservation(1, CPose3D(500, 40, -300, 0.3, 0.2, 0.1));
        expectTrackedEqualsScratch(m, "far move, " + name);
        EXPECT_NEAR(m.revertLastMove(), before, 1e-9) << name;
        expectTrackedEqualsScratch(m, "far move reverted, " + name);
        EXPECT_EQ(m.observationPose(1), CPose3D(0.1, 0, 0.2, 0, 0, 0));

        const CPose3D last(0.3, 0.05, 0.1, 0.05, 0, 0);
        m.moveObservations(
            {{1, CPose3D(2, 0, 0, 0, 0, 0)}, {0, CPose3D(0, 0, 0.1, 0, 0, 0)}, {1, last}});
        EXPECT_EQ(m.observationPose(1), last) << name;
        expectTrackedEqualsScratch(m, "repeated index, " + name);
        EXPECT_NEAR(m.revertLastMove(), before, 1e-9) << name;
        EXPECT_EQ(m.observationPose(0), CPose3D());
        expectTrackedEqualsScratch(m, "repeated index reverted, " + name);
    }
}

TEST(CEntropyVoxelMap, createdFromIniThroughMultiMetricMap)
{
    mrpt::config::CConfigFileMemory ini(INI_TEXT);
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(ini, "Map");
    mrpt::maps::CMultiMetricMap mm(inits);
    auto m = mm.mapByClass<CEntropyVoxelMap>();
    ASSERT_TRUE(m);
    EXPECT_DOUBLE_EQ(m->creationOptions().cell_size, 0.35);
    EXPECT_EQ(m->creationOptions().energy, EnergyType::PlanarStructured);
    EXPECT_EQ(m->creationOptions().dof, 3);
    EXPECT_DOUBLE_EQ(m->insertionOptions.max_range, 12.5);
    EXPECT_DOUBLE_EQ(m->insertionOptions.min_range, 0.2);
    EXPECT_EQ(m->insertionOptions.decimation, 2);
    EXPECT_EQ(m->drawOptions.max_cubes, 1234);
    EXPECT_DOUBLE_EQ(m->drawOptions.min_cube_size, 0.3);

    // Observations reach our map through the CMultiMetricMap.
    mm.insertObservation(*pointCloudObs(makeRoom(1, 0.2)), CPose3D(1, 0, 0, 0, 0, 0));
    ASSERT_EQ(m->observationCount(), 1u);
    EXPECT_EQ(m->observationPose(0), CPose3D(1, 0, 0, 0, 0, 0));
    EXPECT_GT(m->energy(), 0);
}

TEST(CEntropyVoxelMap, rangeScanPointsAreBroughtToTheOpticalFrame)
{
    // One point 2 m straight ahead in MRPT's sensor frame (+X forward): on the
    // optical axis (+z) once sensorPose = opticalFromMrptSensor().
    auto scan = mrpt::obs::CObservation3DRangeScan::Create();
    scan->hasPoints3D = true;
    scan->points3D_x = {2.0f, 0.0f};
    scan->points3D_y = {0.0f, 0.0f};  // second point (0,0,0) = invalid, dropped
    scan->points3D_z = {0.0f, 0.0f};
    scan->sensorPose = CEntropyVoxelMap::opticalFromMrptSensor();
    CEntropyVoxelMap m;
    const CPose3D T_world_cam(0.5, 0, 0, 0, 0, 0);
    ASSERT_TRUE(m.insertObservation(*scan, T_world_cam));
    ASSERT_EQ(m.observationCount(), 1u);
    const auto& c = m.observationCloud(0);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_NEAR(c.points[0].x, 0.0, 1e-6);
    EXPECT_NEAR(c.points[0].y, 0.0, 1e-6);
    EXPECT_NEAR(c.points[0].z, 2.0, 1e-6);
    EXPECT_EQ(m.observationPose(0), T_world_cam);
    // A point left of the sensor (+Y) is at optical -x; above (+Z) at -y.
    const auto R = CEntropyVoxelMap::opticalFromMrptSensor();
    const auto p = R.composePoint(mrpt::math::TPoint3D(0, 1, 2));
    EXPECT_NEAR(p.x, -1, 1e-12);
    EXPECT_NEAR(p.y, -2, 1e-12);
    EXPECT_NEAR(p.z, 0, 1e-12);
}

TEST(CEntropyVoxelMap, serializationRoundTrip)
{
    emslam::maps::registerAllClasses();
    CEntropyVoxelMap m(creation(EnergyType::LowStructured, 0.2));
    m.insertionOptions.decimation = 3;
    m.drawOptions.max_cubes = 77;
    m.insertWeightedCloud(makeRoom(1, 0.15), CPose3D(0.1, 0.2, 0.3, 0.1, 0.2, 0.3));
    m.insertWeightedCloud(makeRoom(2, 0.15), CPose3D(-0.1, 0, 0.5, -0.2, 0, 0.05));

    mrpt::io::CMemoryStream buf;
    auto arch = mrpt::serialization::archiveFrom(buf);
    arch << m;
    buf.Seek(0);
    auto obj = arch.ReadObject();
    auto m2 = std::dynamic_pointer_cast<CEntropyVoxelMap>(obj);
    ASSERT_TRUE(m2);
    EXPECT_EQ(m2->GetRuntimeClass()->className, std::string("emslam::CEntropyVoxelMap"));
    ASSERT_EQ(m2->observationCount(), 2u);
    EXPECT_EQ(m2->creationOptions().energy, EnergyType::LowStructured);
    EXPECT_DOUBLE_EQ(m2->creationOptions().cell_size, 0.2);
    EXPECT_EQ(m2->insertionOptions.decimation, 3);
    EXPECT_EQ(m2->drawOptions.max_cubes, 77);
    for (std::size_t i = 0; i < 2; i++)
    {
        EXPECT_EQ(m2->observationPose(i), m.observationPose(i));
        EXPECT_EQ(m2->observationCloud(i).points, m.observationCloud(i).points);
        EXPECT_EQ(m2->observationCloud(i).weights, m.observationCloud(i).weights);
    }
    EXPECT_NEAR(m2->energy(), m.energy(), 1e-12);  // rebuilt vs incremental: rounding only
    const auto e1 = m.entropies(), e2 = m2->entropies();
    for (std::size_t t = 0; t < e1.size(); t++)
    {
        EXPECT_NEAR(e1[t], e2[t], 1e-12);
    }
}

TEST(CEntropyVoxelMap, optionsSaveLoadRoundTrip)
{
    CEntropyVoxelMap::TCreationOptions c1 = creation(EnergyType::PlanarLowStructured, 0.35);
    CEntropyVoxelMap::TInsertionOptions i1;
    i1.max_range = 7.5;
    i1.min_range = 0.4;
    i1.decimation = 5;
    CEntropyVoxelMap::TDrawOptions d1;
    d1.max_cubes = 99;
    d1.min_cube_size = 0.5;

    mrpt::config::CConfigFileMemory c;
    c1.saveToConfigFile(c, "creation");
    i1.saveToConfigFile(c, "insert");
    d1.saveToConfigFile(c, "draw");
    mrpt::config::CConfigFileMemory reparsed(c.getContent());
    CEntropyVoxelMap::TCreationOptions c2;
    CEntropyVoxelMap::TInsertionOptions i2;
    CEntropyVoxelMap::TDrawOptions d2;
    c2.loadFromConfigFile(reparsed, "creation");
    i2.loadFromConfigFile(reparsed, "insert");
    d2.loadFromConfigFile(reparsed, "draw");
    EXPECT_DOUBLE_EQ(c2.cell_size, 0.35);
    EXPECT_EQ(c2.energy, EnergyType::PlanarLowStructured);
    EXPECT_EQ(c2.dof, 3);
    EXPECT_DOUBLE_EQ(i2.max_range, 7.5);
    EXPECT_DOUBLE_EQ(i2.min_range, 0.4);
    EXPECT_EQ(i2.decimation, 5);
    EXPECT_EQ(d2.max_cubes, 99);
    EXPECT_DOUBLE_EQ(d2.min_cube_size, 0.5);
}

TEST(CEntropyVoxelMap, invalidOptionsThrowNamingTheKey)
{
    const auto load = [](const std::string& body)
    {
        mrpt::config::CConfigFileMemory c("[s]\n" + body);
        CEntropyVoxelMap::TCreationOptions o;
        o.loadFromConfigFile(c, "s");
    };
    using emslam::test::expectThrowContaining;
    expectThrowContaining([&] { load("cell_size = 0\n"); }, {"cell_size", "> 0"});
    expectThrowContaining([&] { load("cell_size = -0.1\n"); }, {"cell_size"});
    // 1e-9 m made the cell keys overflow (a heap write out of bounds).
    expectThrowContaining([&] { load("cell_size = 1e-9\n"); }, {"cell_size", "[0.01, 100]"});
    expectThrowContaining([&] { load("cell_size = 1e9\n"); }, {"cell_size", "[0.01, 100]"});
    EXPECT_NO_THROW(load("cell_size = 0.01\n"));
    expectThrowContaining([&] { load("energy = entropic\n"); }, {"energy", "entropic"});
    expectThrowContaining([&] { load("dof = 4\n"); }, {"dof", "3 or 6"});
    expectThrowContaining([&] { load("energy = structured\ndof = 3\n"); }, {"energy", "dof"});
    expectThrowContaining(
        [&] { load("energy = planar_structured\ndof = 6\n"); }, {"planar_structured", "dof"});
    EXPECT_NO_THROW(load("energy = planar_structured\n"));  // dof follows the energy

    const auto loadInsert = [](const std::string& body)
    {
        mrpt::config::CConfigFileMemory c("[s]\n" + body);
        CEntropyVoxelMap::TInsertionOptions o;
        o.loadFromConfigFile(c, "s");
    };
    expectThrowContaining([&] { loadInsert("decimation = 0\n"); }, {"decimation"});
    expectThrowContaining([&] { loadInsert("max_range = -1\n"); }, {"max_range"});

    // Through CMultiMetricMap as well.
    std::string text = INI_TEXT;
    text.replace(text.find("cell_size = 0.35"), 16, "cell_size = -2.0");
    mrpt::config::CConfigFileMemory ini(text);
    mrpt::maps::TSetOfMetricMapInitializers inits;
    expectThrowContaining([&] { inits.loadFromConfigFile(ini, "Map"); }, {"cell_size"});

    CEntropyVoxelMap::TCreationOptions bad;
    bad.cell_size = 0;
    expectThrowContaining([&] { CEntropyVoxelMap m(bad); }, {"cell_size"});
}

TEST(CEntropyVoxelMap, savedSceneLoadsBack)
{
    CEntropyVoxelMap m(creation(EnergyType::Structured));
    m.insertWeightedCloud(makeRoom(1, 0.1), CPose3D());
    m.insertWeightedCloud(makeRoom(2, 0.1), CPose3D(0.2, 0, 0, 0, 0, 0));

    mrpt::opengl::COpenGLScene scene;
    auto objs = mrpt::opengl::CSetOfObjects::Create();
    m.getVisualizationInto(*objs);
    ASSERT_EQ(objs->size(), 1u);
    auto tris = std::dynamic_pointer_cast<mrpt::opengl::CSetOfTriangles>(*objs->begin());
    ASSERT_TRUE(tris);
    const std::size_t cubes = std::min<std::size_t>(
        m.trackedHistogram(EntropyTerm::H3D)->occupiedCells(),
        static_cast<std::size_t>(m.drawOptions.max_cubes));
    EXPECT_EQ(tris->getTrianglesCount(), 12 * cubes);
    scene.insert(objs);

    const std::string dir = emslam::test::makeTempDir("maps_scene");
    const std::string file = dir + "/map.3Dscene";
    ASSERT_TRUE(scene.saveToFile(file));
    mrpt::opengl::COpenGLScene loaded;
    ASSERT_TRUE(loaded.loadFromFile(file));
    auto back = loaded.getByClass<mrpt::opengl::CSetOfTriangles>();
    ASSERT_TRUE(back);
    EXPECT_EQ(back->getTrianglesCount(), tris->getTrianglesCount());

    m.saveMetricMapRepresentationToFile(dir + "/map");
    EXPECT_TRUE(mrpt::system::fileExists(dir + "/map.3Dscene"));
    EXPECT_TRUE(mrpt::system::fileExists(dir + "/map_cells.txt"));
}

TEST(CEntropyVoxelMap, likelihoodPrefersTheTruePose)
{
    CEntropyVoxelMap m(creation(EnergyType::Structured));
    m.insertWeightedCloud(makeRoom(1, 0.1), CPose3D());
    const auto obs = pointCloudObs(makeRoom(2, 0.1));
    const double at_true = m.computeObservationLikelihood(*obs, CPose3D());
    const double shifted = m.computeObservationLikelihood(*obs, CPose3D(0.4, 0, 0.3, 0, 0, 0));
    const double rotated = m.computeObservationLikelihood(*obs, CPose3D(0, 0, 0, 0, 8 * DEG, 0));
    EXPECT_LE(at_true, 1e-9);
    EXPECT_GT(at_true, shifted);
    EXPECT_GT(at_true, rotated);
    EXPECT_EQ(m.observationCount(), 1u);  // const: not inserted
}

TEST(CEntropyVoxelMap, shippedConfigLoads)
{
    const std::string path = emslam::test::sourceDir() + "/config/maps/entropy-map.ini";
    ASSERT_TRUE(mrpt::system::fileExists(path)) << path;
    mrpt::config::CConfigFile ini(path);
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(ini, "EntropyVoxelMap");
    mrpt::maps::CMultiMetricMap mm(inits);
    auto m = mm.mapByClass<CEntropyVoxelMap>();
    ASSERT_TRUE(m);
    EXPECT_DOUBLE_EQ(m->creationOptions().cell_size, 0.15);
    EXPECT_EQ(m->creationOptions().energy, EnergyType::Structured);
    EXPECT_EQ(m->creationOptions().dof, 6);
}

TEST(CEntropyVoxelMap, rangeImageWithoutPointsIsUnprojected)
{
    auto scan = mrpt::obs::CObservation3DRangeScan::Create();
    scan->cameraParams.ncols = 8;
    scan->cameraParams.nrows = 6;
    scan->cameraParams.fx(500);
    scan->cameraParams.fy(500);
    scan->cameraParams.cx(4);
    scan->cameraParams.cy(3);
    scan->range_is_depth = true;
    scan->rangeUnits = 0.001f;
    scan->hasRangeImage = true;
    scan->rangeImage_setSize(6, 8);
    scan->rangeImage.fill(2000);  // 2 m everywhere
    scan->hasPoints3D = false;
    scan->sensorPose = CEntropyVoxelMap::opticalFromMrptSensor();
    CEntropyVoxelMap m;
    ASSERT_TRUE(m.insertObservation(*scan));
    ASSERT_EQ(m.observationCount(), 1u);
    const auto& c = m.observationCloud(0);
    ASSERT_EQ(c.size(), 1u);  // 48 points within a few mm: one l_d cell
    EXPECT_FLOAT_EQ(c.weights[0], 48.0f);
    EXPECT_NEAR(c.points[0].z, 2.0, 1e-3);
    EXPECT_NEAR(c.points[0].x, 0.0, 0.01);
    EXPECT_NEAR(c.points[0].y, 0.0, 0.01);
}

namespace
{
/** Every tracked entropy equals a from-scratch computation. */
void expectTrackedMatchScratch(const CEntropyVoxelMap& m)
{
    const auto scratch = m.computeEntropiesFromScratch();
    for (std::size_t t = 0; t < emslam::maps::NUM_ENTROPY_TERMS; ++t)
    {
        if (const auto* h = m.trackedHistogram(static_cast<emslam::maps::EntropyTerm>(t)))
        {
            ASSERT_NEAR(h->entropy(), scratch[t], 1e-9) << "term " << t;
        }
    }
}

/** Random moves, batches and reverts of 8 clouds; `spread` decides whether
 * the marginals fit the dense per-move grids (small) or fall back to hashing. */
void checkRandomMoves(
    emslam::maps::EnergyType energy, bool integral_weights, double spread, std::size_t points)
{
    CEntropyVoxelMap::TCreationOptions o;
    o.cell_size = 0.15;
    o.energy = energy;
    o.dof = emslam::maps::energyDof(energy);
    CEntropyVoxelMap m(o);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 8; ++i)
    {
        emslam::maps::WeightedPointCloud c;
        for (std::size_t j = 0; j < points; ++j)
        {
            const float w = integral_weights ? static_cast<float>(1 + (j % 7))
                                             : static_cast<float>(0.3 + 2 * std::abs(u(rng)));
            c.push_back(
                mrpt::math::TPoint3Df(
                    static_cast<float>(spread * u(rng)), static_cast<float>(spread * u(rng)),
                    static_cast<float>(spread * u(rng))),
                w);
        }
        m.insertWeightedCloud(c, CPose3D(0.1 * i, 0, 0.3 * i, 0, 0, 0), true);
    }
    expectTrackedMatchScratch(m);
    for (int k = 0; k < 200; ++k)
    {
        const std::size_t i = static_cast<std::size_t>(k % 8);
        const CPose3D d(
            0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng));
        const double before = m.energy();
        if (k % 3 == 0)
        {
            const std::size_t j = (i + 3) % 8;
            m.moveObservations(
                {{i, m.observationPose(i) + d},
                 {j, m.observationPose(j) + d},
                 {i, m.observationPose(i) + d + d}});
        }
        else
        {
            m.moveObservation(i, m.observationPose(i) + d);
        }
        expectTrackedMatchScratch(m);
        if (k % 2 == 0)
        {
            ASSERT_NEAR(m.revertLastMove(), before, 1e-9);
            expectTrackedMatchScratch(m);
        }
    }
    ASSERT_NEAR(m.energy(), m.recomputeFromScratch(), 1e-9);
}
}  // namespace

TEST(CEntropyVoxelMap, incrementalMovesMatchForFractionalWeightsAndSparseClouds)
{
    for (int e = 0; e < 5; ++e)
    {
        for (bool integral : {true, false})
        {
            SCOPED_TRACE("energy " + std::to_string(e) + (integral ? " integral" : " fractional"));
            checkRandomMoves(static_cast<emslam::maps::EnergyType>(e), integral, 2.0, 500);
            checkRandomMoves(static_cast<emslam::maps::EnergyType>(e), integral, 60.0, 20);
        }
    }
}
