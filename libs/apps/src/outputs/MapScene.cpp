// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/EntropyVoxelObject.h>
#include <emslam/apps/MapScene.h>
#include <emslam/apps/MapStyle.h>
#include <emslam/io/AtomicFile.h>
#include <emslam/io/GzOutputStream.h>

#include <mrpt/core/format.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CText.h>
#include <mrpt/opengl/stock_objects.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace emslam::apps
{
namespace
{
mrpt::opengl::CSetOfLines::Ptr trajectoryLines(
    const emslam::io::TumTrajectory& t, const TrajectoryStyle& style, const char* name)
{
    auto lines = mrpt::opengl::CSetOfLines::Create();
    lines->setName(name);
    lines->setColor(style.r, style.g, style.b);
    lines->setLineWidth(2.0f);
    for (std::size_t i = 1; i < t.size(); ++i)
    {
        const auto& p = t.poses[i - 1].pose;
        const auto& q = t.poses[i].pose;
        lines->appendLine(p.x(), p.y(), p.z(), q.x(), q.y(), q.z());
    }
    return lines;
}

/** The 2nd and 98th percentiles of the heights: a few stray points must not
 * squeeze every other colour together. */
std::pair<double, double> heightRange(const slam::IntensityCloud& cloud)
{
    if (cloud.empty())
    {
        return {0.0, 1.0};
    }
    std::vector<double> h;
    h.reserve(cloud.size());
    for (const auto& p : cloud.points)
    {
        h.push_back(heightAboveFirstCamera(p));
    }
    const auto at = [&](double f)
    {
        auto it = h.begin() + static_cast<std::ptrdiff_t>(f * static_cast<double>(h.size() - 1));
        std::nth_element(h.begin(), it, h.end());
        return *it;
    };
    const double lo = at(0.02), hi = at(0.98);
    return {lo, std::max(hi, lo + 0.1)};
}

/** Bounding box of the trajectories in the viewer frame (empty: lo > hi). */
void trajectoryBox(const MapDrawingContent& c, mrpt::math::TPoint3D& lo, mrpt::math::TPoint3D& hi)
{
    lo = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    hi = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    const auto T = viewerFromCamera();
    for (const auto* t : {c.slam, c.egomotion, c.ground_truth})
    {
        if (!t)
        {
            continue;
        }
        for (const auto& p : t->poses)
        {
            const auto q = (T + p.pose).asTPose().translation();
            lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
            hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
        }
    }
}

void addLegendLine(
    mrpt::opengl::CSetOfObjects& legend,
    const std::string& text,
    const mrpt::img::TColorf& color,
    double x,
    double y,
    double z)
{
    auto label = mrpt::opengl::CText::Create(text);
    label->setColor(color.R, color.G, color.B);
    label->setLocation(x, y, z);
    legend.insert(label);
}
/** The map cloud (coloured by height, its range in `range`), trajectories,
 * loop closures, entropy voxels and axes, in the viewer frame. */
mrpt::opengl::CSetOfObjects::Ptr mapObjects(
    const MapDrawingContent& c, std::pair<double, double>& range)
{
    auto world = mrpt::opengl::CSetOfObjects::Create();
    world->setName("map frame (first camera)");
    world->setPose(viewerFromCamera());

    slam::IntensityCloud kept;
    if (c.cloud)
    {
        kept = cutAboveHeight(*c.cloud, c.max_height);
        range = heightRange(kept);
        auto cloud = mrpt::opengl::CPointCloudColoured::Create();
        cloud->setName(MAP_CLOUD_NAME);
        cloud->reserve(kept.size());
        for (const auto& p : kept.points)
        {
            const auto col = heightColor(heightAboveFirstCamera(p), range.first, range.second);
            cloud->push_back(p.x, p.y, p.z, col.R, col.G, col.B);
        }
        cloud->setPointSize(2.0f);
        world->insert(cloud);
    }
    if (c.egomotion)
    {
        world->insert(trajectoryLines(*c.egomotion, EGOMOTION_STYLE, EGOMOTION_NAME));
    }
    if (c.slam)
    {
        world->insert(trajectoryLines(*c.slam, SLAM_STYLE, SLAM_NAME));
    }
    if (c.ground_truth && !c.ground_truth->empty())
    {
        world->insert(trajectoryLines(*c.ground_truth, GROUND_TRUTH_STYLE, GROUND_TRUTH_NAME));
    }
    if (c.loops && !c.loops->empty())
    {
        auto lines = mrpt::opengl::CSetOfLines::Create();
        lines->setName(LOOPS_NAME);
        lines->setColor(LOOP_STYLE.r, LOOP_STYLE.g, LOOP_STYLE.b);
        lines->setLineWidth(1.0f);
        for (const auto& [a, b] : *c.loops)
        {
            lines->appendLine(a.x, a.y, a.z, b.x, b.y, b.z);
        }
        world->insert(lines);
    }
    if (c.entropy_map)
    {
        world->insert(entropyVoxelObject(*c.entropy_map, c.max_voxels));
    }
    world->insert(mrpt::opengl::stock_objects::CornerXYZ(0.5f));
    return world;
}

/** The legend, in the viewer frame: a column of labels beside the map
 * (lines `step` apart, above the top-left corner of lo..hi). */
mrpt::opengl::CSetOfObjects::Ptr legendObjects(
    const MapDrawingContent& c,
    const std::pair<double, double>& range,
    const mrpt::math::TPoint3D& lo,
    const mrpt::math::TPoint3D& hi,
    double step)
{
    auto legend = mrpt::opengl::CSetOfObjects::Create();
    legend->setName(LEGEND_NAME);
    // Seen from above with the scene's camera, viewer +Y is the screen's up:
    // the lines stack downwards from above the map's top-left corner.
    const double x = lo.x, z = hi.z + 1.0;
    double y = hi.y + 7 * step;
    const auto next = [&] { return y -= step; };
    if (c.cloud)
    {
        std::string cut;
        if (!std::isinf(c.max_height))
        {
            cut = mrpt::format(", cut above %.2f m", c.max_height);
        }
        addLegendLine(
            *legend,
            mrpt::format(
                "map cloud: height above the first camera, blue %.1f m .. red %.1f m%s",
                range.first, range.second, cut.c_str()),
            heightColor(0.5 * (range.first + range.second), range.first, range.second), x, y, z);
        next();
    }
    for (const auto& [traj, style] :
         {std::make_pair(c.egomotion, EGOMOTION_STYLE), std::make_pair(c.slam, SLAM_STYLE),
          std::make_pair(c.ground_truth, GROUND_TRUTH_STYLE)})
    {
        if (traj && !traj->empty())
        {
            addLegendLine(
                *legend, std::string(style.label) + " trajectory",
                mrpt::img::TColorf(style.r, style.g, style.b), x, y, z);
            next();
        }
    }
    if (c.loops && !c.loops->empty())
    {
        addLegendLine(
            *legend, mrpt::format("loop closures: %zu", c.loops->size()),
            mrpt::img::TColorf(LOOP_STYLE.r, LOOP_STYLE.g, LOOP_STYLE.b), x, y, z);
        next();
    }
    if (c.entropy_map)
    {
        addLegendLine(
            *legend, "entropy voxels: cell mass, dark red light .. white heavy",
            mrpt::img::TColorf(1.0f, 0.6f, 0.2f), x, y, z);
        next();
    }
    addLegendLine(
        *legend, "axes: first camera (X forward, Y left, Z up), grid 5 m",
        mrpt::img::TColorf(0.9f, 0.9f, 0.9f), x, y, z);
    return legend;
}
}  // namespace

mrpt::opengl::COpenGLScene::Ptr buildMapScene(const MapDrawingContent& c)
{
    std::pair<double, double> range{0.0, 1.0};
    auto world = mapObjects(c, range);
    auto scene = mrpt::opengl::COpenGLScene::Create();
    scene->insert(mrpt::opengl::CGridPlaneXY::Create(-50, 50, -50, 50, 0, 5));
    scene->insert(world);

    mrpt::math::TPoint3D lo, hi;
    trajectoryBox(c, lo, hi);
    if (lo.x > hi.x)
    {
        lo = {-5, -5, 0};
        hi = {5, 5, 0};
    }
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, 5.0});
    scene->insert(legendObjects(c, range, lo, hi, extent / 15.0));

    auto& cam = scene->getViewport()->getCamera();
    cam.setPointingAt(
        static_cast<float>(0.5 * (lo.x + hi.x)), static_cast<float>(0.5 * (lo.y + hi.y)),
        static_cast<float>(0.5 * (lo.z + hi.z)));
    cam.setZoomDistance(static_cast<float>(2.0 * extent));
    cam.setElevationDegrees(70.0f);
    cam.setAzimuthDegrees(-90.0f);
    scene->enableFollowCamera(true);
    return scene;
}

void writeSceneFile(const mrpt::opengl::COpenGLScene& scene, const std::string& file)
{
    emslam::io::writeFileAtomically(
        file,
        [&](const std::string& partial)
        {
            // As COpenGLScene::saveToFile() writes it (gzip level 1), but every
            // write error thrown with the file's name and the OS reason.
            emslam::io::GzOutputStream f(partial, 1, file);
            mrpt::serialization::archiveFrom(f) << scene;
            f.close();
            return true;
        });
}

void writeMapScene(const MapDrawingContent& content, const std::string& file)
{
    writeSceneFile(*buildMapScene(content), file);
}

}  // namespace emslam::apps
