// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/EntropyVoxelObject.h>
#include <emslam/apps/MapScene.h>
#include <emslam/apps/MapStyle.h>

#include <mrpt/img/color_maps.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/stock_objects.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>
#include <vector>

namespace emslam::apps
{
mrpt::opengl::CSetOfObjects::Ptr entropyVoxelObject(
    const emslam::CEntropyVoxelMap& map, std::size_t max_cells)
{
    using emslam::maps::EntropyTerm;
    const emslam::maps::WeightedHistogram* h3 = map.trackedHistogram(EntropyTerm::H3D);
    emslam::maps::WeightedHistogram built;
    if (!h3)
    {
        built = map.buildHistogram(EntropyTerm::H3D);
        h3 = &built;
    }
    std::vector<std::pair<double, std::uint64_t>> cells;
    cells.reserve(h3->occupiedCells());
    h3->forEachCell(
        [&](std::uint64_t key, double w)
        {
            if (w > 0)
            {
                cells.emplace_back(w, key);
            }
        });
    const auto heavier = [](const auto& a, const auto& b)
    { return a.first != b.first ? a.first > b.first : a.second < b.second; };
    if (cells.size() > max_cells)
    {
        std::nth_element(cells.begin(), cells.begin() + max_cells, cells.end(), heavier);
        cells.resize(max_cells);
    }
    std::sort(cells.begin(), cells.end(), heavier);

    auto points = mrpt::opengl::CPointCloudColoured::Create();
    points->setPointSize(4.0f);
    const double l = map.creationOptions().cell_size;
    const double w_max = cells.empty() ? 1.0 : cells.front().first;
    for (const auto& [w, key] : cells)
    {
        const auto c = emslam::maps::unpackCellKey(key);
        float r = 0, g = 0, b = 0;
        // Cube root: masses span orders of magnitude; this keeps light cells visible.
        mrpt::img::hot2rgb(static_cast<float>(0.25 + 0.75 * std::cbrt(w / w_max)), r, g, b);
        points->push_back(
            static_cast<float>((c.x + 0.5) * l), static_cast<float>((c.y + 0.5) * l),
            static_cast<float>((c.z + 0.5) * l), r, g, b);
    }
    auto set = mrpt::opengl::CSetOfObjects::Create();
    set->setName(ENTROPY_VOXELS_NAME);
    set->insert(points);
    return set;
}

mrpt::opengl::COpenGLScene::Ptr buildEntropyMapScene(
    const emslam::CEntropyVoxelMap& map, std::size_t max_cells)
{
    auto world = mrpt::opengl::CSetOfObjects::Create();
    world->setPose(viewerFromCamera());
    world->insert(entropyVoxelObject(map, max_cells));
    world->insert(mrpt::opengl::stock_objects::CornerXYZ(0.5f));

    auto scene = mrpt::opengl::COpenGLScene::Create();
    scene->insert(world);
    auto& cam = scene->getViewport()->getCamera();
    cam.setZoomDistance(30.0f);
    cam.setElevationDegrees(60.0f);
    cam.setAzimuthDegrees(-90.0f);
    scene->enableFollowCamera(true);
    return scene;
}

void writeEntropyMapScene(
    const emslam::CEntropyVoxelMap& map, std::size_t max_cells, const std::string& file)
{
    writeSceneFile(*buildEntropyMapScene(map, max_cells), file);
}

}  // namespace emslam::apps
