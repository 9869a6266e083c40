// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/EntropyVoxelObject.h>
#include <emslam/apps/LiveViewer.h>
#include <emslam/apps/MapStyle.h>
#include <emslam/apps/MapViewApp.h>
#include <emslam/io/InputFileChecks.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CMetricMap.h>
#include <mrpt/opengl/CFBORender.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <thread>

namespace emslam::apps
{
namespace
{
constexpr const char* PROGRAM = "emslam-mapview";
/** The window and --screenshot image size [px]. */
constexpr unsigned WINDOW_WIDTH = 1000, WINDOW_HEIGHT = 700;

bool endsWith(const std::string& s, const std::string& tail)
{
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
}  // namespace

MapViewApp::MapViewApp() : App(PROGRAM) {}

bool MapViewApp::parseArguments(int argc, const char** argv)
{
    TCLAP::CmdLine cmd(
        "emslam-mapview: opens emslam's map files in a 3D window: entropy_map.bin (the entropy "
        "voxels), any serialized MRPT metric map, or a .3Dscene (map.3Dscene).",
        ' ', "0.1");
    TCLAP::UnlabeledValueArg<std::string> file(
        "file", "entropy_map.bin, a serialized metric map, or a .3Dscene", true, "", "FILE", cmd);
    TCLAP::ValueArg<long long> max_cells(
        "", "max-cells", "Entropy cells drawn at most (the heaviest; default 50000)", false, 50000,
        "N", cmd);
    TCLAP::ValueArg<std::string> screenshot(
        "", "screenshot",
        "Draws the view off-screen (no display needed) into this image file (PNG by its "
        "extension) instead of opening the window",
        false, "", "FILE", cmd);
    if (!parseCommandLine(cmd, argc, argv))
    {
        return false;
    }
    if (max_cells.getValue() < 1)
    {
        throw std::invalid_argument("--max-cells must be >= 1");
    }
    m_file = file.getValue();
    m_max_cells = static_cast<std::size_t>(max_cells.getValue());
    m_screenshot = screenshot.getValue();
    return true;
}

mrpt::opengl::COpenGLScene::Ptr MapViewApp::loadScene(
    const std::string& file, std::size_t max_cells)
{
    io::requireInputFile(file, "map file");
    if (endsWith(file, ".3Dscene"))
    {
        auto scene = mrpt::opengl::COpenGLScene::Create();
        if (!scene->loadFromFile(file))
        {
            throw std::runtime_error("'" + file + "' is not a readable .3Dscene");
        }
        return scene;
    }
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
        // Also reads uncompressed files (entropy_map.bin is not compressed).
        mrpt::io::CFileGZInputStream f(file);
        obj = mrpt::serialization::archiveFrom(f).ReadObject();
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error(
            "'" + file +
            "' is not a serialized MRPT object: " + emslam::util::shortExceptionMessage(e));
    }
    if (const auto entropy = std::dynamic_pointer_cast<emslam::CEntropyVoxelMap>(obj))
    {
        return buildEntropyMapScene(*entropy, max_cells);
    }
    if (const auto map = std::dynamic_pointer_cast<mrpt::maps::CMetricMap>(obj))
    {
        auto drawing = mrpt::opengl::CSetOfObjects::Create();
        map->getVisualizationInto(*drawing);
        auto scene = mrpt::opengl::COpenGLScene::Create();
        scene->insert(drawing);
        return scene;
    }
    throw std::runtime_error(
        "'" + file + "' holds a " + obj->GetRuntimeClass()->className +
        ", not a metric map or a 3D scene");
}

void MapViewApp::saveScreenshot(const mrpt::opengl::COpenGLScene& scene) const
{
    // Off-screen (EGL): no display needed, the scene's own camera.
    mrpt::opengl::CFBORender render(WINDOW_WIDTH, WINDOW_HEIGHT);
    render.setCamera(scene, scene.getViewport()->getCamera());
    mrpt::img::CImage image;
    render.render_RGB(scene, image);
    if (!image.saveToFile(m_screenshot))
    {
        throw std::runtime_error("cannot write the screenshot '" + m_screenshot + "'");
    }
}

void MapViewApp::execute()
{
    auto scene = loadScene(m_file, m_max_cells);
    if (!m_screenshot.empty())
    {
        saveScreenshot(*scene);
        return;
    }
    const std::string problem = LiveViewer::displayProblem();
    if (!problem.empty())
    {
        throw std::runtime_error("cannot show '" + m_file + "': " + problem);
    }
    mrpt::gui::CDisplayWindow3D win(
        std::string(PROGRAM) + ": " + m_file, WINDOW_WIDTH, WINDOW_HEIGHT);
    // The toolkit only prints why a window failed (no GLX on the display, a
    // GL context refused) and times out: nothing would be shown, so fail.
    if (!win.isOpen())
    {
        throw std::runtime_error(
            "cannot show '" + m_file + "': no window opened on display '" + std::getenv("DISPLAY") +
            "' (no OpenGL / GLX there? see the toolkit's message above)");
    }
    {
        auto& shown = win.get3DSceneAndLock();
        shown = scene;
        win.unlockAccess3DScene();
    }
    // The window keeps its own camera; start it where the scene's looks from.
    const auto& cam = scene->getViewport()->getCamera();
    win.setCameraZoom(cam.getZoomDistance());
    win.setCameraAzimuthDeg(cam.getAzimuthDegrees());
    win.setCameraElevationDeg(cam.getElevationDegrees());
    win.setCameraPointingToPoint(cam.getPointingAtX(), cam.getPointingAtY(), cam.getPointingAtZ());
    win.addTextMessage(
        0.01, 0.02, "mouse: left drag rotates, right drag / wheel zooms; close the window to quit",
        0);
    win.forceRepaint();
    while (win.isOpen())
    {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
}

}  // namespace emslam::apps
