// SPDX-License-Identifier: BSD-3-Clause
// CEntropyVoxelMap: 3D visualization and file export.
#include <emslam/maps/CEntropyVoxelMap.h>

#include <mrpt/img/color_maps.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CSetOfTriangles.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <utility>
#include <vector>

using emslam::CEntropyVoxelMap;
using emslam::maps::EntropyTerm;

namespace
{
/** Appends the 12 triangles of an axis-aligned cube (outward normals). */
void addCube(
    mrpt::opengl::CSetOfTriangles& tris,
    const mrpt::math::TPoint3Df& c,
    float half,
    const mrpt::img::TColor& color)
{
    using P = mrpt::math::TPoint3Df;
    const P v[8] = {P(c.x - half, c.y - half, c.z - half), P(c.x + half, c.y - half, c.z - half),
                    P(c.x + half, c.y + half, c.z - half), P(c.x - half, c.y + half, c.z - half),
                    P(c.x - half, c.y - half, c.z + half), P(c.x + half, c.y - half, c.z + half),
                    P(c.x + half, c.y + half, c.z + half), P(c.x - half, c.y + half, c.z + half)};
    // Faces as counter-clockwise quads seen from outside.
    static const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                    {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
    for (const auto& f : faces)
    {
        mrpt::opengl::TTriangle t1(v[f[0]], v[f[1]], v[f[2]]);
        mrpt::opengl::TTriangle t2(v[f[0]], v[f[2]], v[f[3]]);
        t1.setColor(color);
        t2.setColor(color);
        tris.insertTriangle(t1);
        tris.insertTriangle(t2);
    }
}
}  // namespace

void CEntropyVoxelMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const
{
    if (!genericMapParams.enableSaveAs3DObject)
    {
        return;
    }
    const emslam::maps::WeightedHistogram* h3 = trackedHistogram(EntropyTerm::H3D);
    emslam::maps::WeightedHistogram built;
    if (!h3)
    {
        built = buildHistogram(EntropyTerm::H3D);
        h3 = &built;
    }
    std::vector<std::pair<double, std::uint64_t>> cells;
    cells.reserve(h3->occupiedCells());
    h3->forEachCell([&](std::uint64_t key, double w) { cells.emplace_back(w, key); });
    // Densest first; ties by key, so the drawing is deterministic.
    std::sort(
        cells.begin(), cells.end(),
        [](const auto& a, const auto& b)
        { return a.first != b.first ? a.first > b.first : a.second < b.second; });
    if (cells.size() > static_cast<std::size_t>(drawOptions.max_cubes))
    {
        cells.resize(static_cast<std::size_t>(drawOptions.max_cubes));
    }
    auto tris = mrpt::opengl::CSetOfTriangles::Create();
    tris->setName("entropy_voxels");
    tris->reserve(cells.size() * 12);
    const double l = m_creation.cell_size;
    const double w_max = cells.empty() ? 1.0 : cells.front().first;
    for (const auto& [w, key] : cells)
    {
        // Volume ∝ density (edge ∝ cube root), as in the paper's Fig. 9.
        const double rel = std::cbrt(w / w_max);
        const double edge = l * std::max(drawOptions.min_cube_size, rel);
        const auto c = emslam::maps::unpackCellKey(key);
        const mrpt::math::TPoint3Df centre(
            static_cast<float>((c.x + 0.5) * l), static_cast<float>((c.y + 0.5) * l),
            static_cast<float>((c.z + 0.5) * l));
        const mrpt::img::TColor color =
            mrpt::img::colormap(mrpt::img::cmJET, static_cast<float>(rel));
        addCube(*tris, centre, static_cast<float>(0.5 * edge), color);
    }
    o.insert(tris);
}

void CEntropyVoxelMap::saveMetricMapRepresentationToFile(const std::string& filNamePrefix) const
{
    {
        std::ofstream f(filNamePrefix + "_cells.txt");
        ASSERTMSG_(f.is_open(), "CEntropyVoxelMap: cannot write " + filNamePrefix + "_cells.txt");
        f << "% x y z weight (centres of the occupied 3D cells, map frame [m])\n";
        const auto h3 = buildHistogram(EntropyTerm::H3D);
        const double l = m_creation.cell_size;
        h3.forEachCell(
            [&](std::uint64_t key, double w)
            {
                const auto c = emslam::maps::unpackCellKey(key);
                f << (c.x + 0.5) * l << ' ' << (c.y + 0.5) * l << ' ' << (c.z + 0.5) * l << ' ' << w
                  << '\n';
            });
    }
    mrpt::opengl::COpenGLScene scene;
    auto objs = mrpt::opengl::CSetOfObjects::Create();
    getVisualizationInto(*objs);
    scene.insert(objs);
    scene.saveToFile(filNamePrefix + ".3Dscene");
}
