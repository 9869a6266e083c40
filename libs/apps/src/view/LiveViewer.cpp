// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/LiveViewer.h>
#include <emslam/apps/MapStyle.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/opengl/CFrustum.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/stock_objects.h>

#ifdef EMSLAM_HAVE_X11
#include <X11/Xlib.h>
#endif

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <utility>

namespace emslam::apps
{
namespace
{
using Clock = std::chrono::steady_clock;

/** Unique indices of the window's text lines. */
enum TextLine : std::size_t
{
    LEGEND_FIRST = 0,
    STATUS = 10
};

mrpt::opengl::CSetOfLines::Ptr linesOf(const TrajectoryStyle& style)
{
    auto lines = mrpt::opengl::CSetOfLines::Create();
    lines->setColor(style.r, style.g, style.b);
    lines->setLineWidth(2.0f);
    return lines;
}

void setPolyline(mrpt::opengl::CSetOfLines& lines, const std::vector<mrpt::math::TPoint3Df>& p)
{
    lines.clear();
    for (std::size_t i = 1; i < p.size(); ++i)
    {
        lines.appendLine(p[i - 1].x, p[i - 1].y, p[i - 1].z, p[i].x, p[i].y, p[i].z);
    }
}

mrpt::opengl::TFontParams font(float r, float g, float b)
{
    mrpt::opengl::TFontParams f;
    f.color = mrpt::img::TColorf(r, g, b);
    f.vfont_scale = 14.0f;
    f.draw_shadow = true;
    return f;
}

/** What the viewer thread draws into. */
struct SceneObjects
{
    mrpt::opengl::CSetOfObjects::Ptr world;
    mrpt::opengl::CPointCloudColoured::Ptr cloud;
    mrpt::opengl::CSetOfLines::Ptr egomotion, slam, loops;
    mrpt::opengl::CSetOfObjects::Ptr camera;
    mrpt::opengl::COpenGLViewport::Ptr image;
};

SceneObjects createScene(mrpt::opengl::COpenGLScene& scene)
{
    SceneObjects o;
    scene.getViewport()->setCustomBackgroundColor(mrpt::img::TColorf(0.08f, 0.08f, 0.12f));
    auto grid = mrpt::opengl::CGridPlaneXY::Create(-50, 50, -50, 50, 0, 5);
    grid->setColor(0.4f, 0.4f, 0.4f);
    scene.insert(grid);
    o.world = mrpt::opengl::CSetOfObjects::Create();
    o.world->setPose(viewerFromCamera());
    o.cloud = mrpt::opengl::CPointCloudColoured::Create();
    o.cloud->setPointSize(2.0f);
    o.egomotion = linesOf(EGOMOTION_STYLE);
    o.slam = linesOf(SLAM_STYLE);
    o.loops = linesOf(LOOP_STYLE);
    o.camera = mrpt::opengl::CSetOfObjects::Create();
    // CFrustum looks along its +X; the camera along its +z.
    auto frustum = mrpt::opengl::CFrustum::Create(0.05f, 0.8f, 70.0f, 50.0f, 2.0f, true, false);
    frustum->setColor(1.0f, 1.0f, 0.2f);
    frustum->setPose(-viewerFromCamera());
    o.camera->insert(frustum);
    o.camera->insert(mrpt::opengl::stock_objects::CornerXYZSimple(0.3f, 2.0f));
    o.camera->setVisibility(false);
    for (const auto& obj :
         {mrpt::opengl::CRenderizable::Ptr(o.cloud), mrpt::opengl::CRenderizable::Ptr(o.egomotion),
          mrpt::opengl::CRenderizable::Ptr(o.slam), mrpt::opengl::CRenderizable::Ptr(o.loops),
          mrpt::opengl::CRenderizable::Ptr(o.camera)})
    {
        o.world->insert(obj);
    }
    scene.insert(o.world);
    o.image = scene.createViewport("image");
    o.image->setViewportPosition(0.66, 0.62, 0.33, 0.37);
    o.image->setTransparent(false);
    o.image->setBorderSize(1);
    return o;
}

void pushGrey(
    mrpt::opengl::CPointCloudColoured& cloud, const slam::IntensityCloud& p, std::size_t from)
{
    for (std::size_t i = from; i < p.size(); ++i)
    {
        const float g = 0.25f + 0.75f * static_cast<float>(p.intensity[i]) / 255.0f;
        cloud.push_back(p.points[i].x, p.points[i].y, p.points[i].z, g, g, g);
    }
}

/** Adds `fresh` to the drawn points; past `max`, every other point is
 * dropped (old areas stay visible, only sparser). */
void appendPoints(
    mrpt::opengl::CPointCloudColoured& cloud,
    slam::IntensityCloud& drawn,
    const slam::IntensityCloud& fresh,
    std::size_t max)
{
    const std::size_t before = drawn.size();
    drawn.points.insert(drawn.points.end(), fresh.points.begin(), fresh.points.end());
    drawn.intensity.insert(drawn.intensity.end(), fresh.intensity.begin(), fresh.intensity.end());
    if (drawn.size() <= max)
    {
        pushGrey(cloud, drawn, before);
        return;
    }
    slam::IntensityCloud thinned;
    for (std::size_t i = 0; i < drawn.size(); i += 2)
    {
        thinned.points.push_back(drawn.points[i]);
        thinned.intensity.push_back(drawn.intensity[i]);
    }
    drawn = std::move(thinned);
    cloud.clear();
    pushGrey(cloud, drawn, 0);
}
/** The legend's lines, top left. */
void addLegend(mrpt::gui::CDisplayWindow3D& win)
{
    std::size_t line = LEGEND_FIRST;
    using Legend = std::pair<TrajectoryStyle, const char*>;
    for (const auto& [style, suffix] :
         {Legend{EGOMOTION_STYLE, " trajectory"}, Legend{SLAM_STYLE, " trajectory"},
          Legend{LOOP_STYLE, ""}})
    {
        win.addTextMessage(
            0.01, 0.97 - 0.035 * static_cast<double>(line), style.label + std::string(suffix), line,
            font(style.r, style.g, style.b));
        ++line;
    }
    win.addTextMessage(
        0.01, 0.97 - 0.035 * static_cast<double>(line), "map points (grey), camera (yellow)", line,
        font(0.85f, 0.85f, 0.85f));
}

/** The snapshot's trajectories, loops, camera and image into the scene
 * (locked); returns where the camera is, to follow it. */
std::optional<mrpt::math::TPoint3D> showSnapshot(
    const SceneObjects& objects, LiveViewSnapshot& snap)
{
    std::optional<mrpt::math::TPoint3D> follow;
    setPolyline(*objects.egomotion, snap.egomotion);
    setPolyline(*objects.slam, snap.slam);
    objects.loops->clear();
    for (const auto& [a, b] : snap.loops)
    {
        objects.loops->appendLine(a.x, a.y, a.z, b.x, b.y, b.z);
    }
    if (snap.camera)
    {
        objects.camera->setPose(*snap.camera);
        objects.camera->setVisibility(true);
        follow = (viewerFromCamera() + *snap.camera).asTPose().translation();
    }
    if (!snap.image.isEmpty())
    {
        objects.image->setImageView(std::move(snap.image));
    }
    return follow;
}
}  // namespace

std::string LiveViewer::displayProblem()
{
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display)
    {
        return "DISPLAY is not set (no X display; 'xvfb-run -a' gives a virtual one)";
    }
#ifdef EMSLAM_HAVE_X11
    // Probing first: the window toolkit aborts the process on a dead display.
    Display* d = XOpenDisplay(nullptr);
    if (!d)
    {
        return std::string("cannot open X display '") + display + "'";
    }
    XCloseDisplay(d);
#endif
    return {};
}

LiveViewer::LiveViewer(const Options& options) : m_options(options)
{
    if (!(m_options.max_rate_hz > 0))
    {
        m_options.max_rate_hz = 10.0;
    }
    const std::string problem = displayProblem();
    if (!problem.empty())
    {
        disable(problem);
        return;
    }
    m_thread = std::thread([this] { run(); });
}

LiveViewer::~LiveViewer()
{
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_all();
    if (m_thread.joinable())
    {
        m_thread.join();
    }
}

void LiveViewer::disable(const std::string& why)
{
    m_active.store(false);
    std::fprintf(
        stderr, "%s: warning: live viewer off: %s; the run goes on without it\n",
        m_options.title.c_str(), why.c_str());
}

void LiveViewer::push(LiveViewSnapshot snapshot)
{
    if (!m_active.load())
    {
        return;
    }
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_pending = std::move(snapshot);
        m_has_pending.store(true);
    }
    m_wake.notify_one();
}

void LiveViewer::addMapPoints(const slam::IntensityCloud& points)
{
    if (!m_active.load() || points.empty())
    {
        return;
    }
    std::lock_guard<std::mutex> lock(m_mutex);
    m_new_points.points.insert(
        m_new_points.points.end(), points.points.begin(), points.points.end());
    m_new_points.intensity.insert(
        m_new_points.intensity.end(), points.intensity.begin(), points.intensity.end());
}

void LiveViewer::run()
{
    mrpt::gui::CDisplayWindow3D::Ptr win;
    SceneObjects objects;
    slam::IntensityCloud drawn_points;
    try
    {
        win =
            mrpt::gui::CDisplayWindow3D::Create(m_options.title, m_options.width, m_options.height);
        win->setPos(0, 0);
        {
            auto& scene = win->get3DSceneAndLock();
            objects = createScene(*scene);
            win->unlockAccess3DScene();
        }
        // The window's own camera (the mouse moves it), not the scene's.
        win->setCameraZoom(25.0f);
        win->setCameraElevationDeg(55.0f);
        win->setCameraAzimuthDeg(-120.0f);
        addLegend(*win);
        win->forceRepaint();
    }
    catch (const std::exception& e)
    {
        disable("cannot open the window: " + emslam::util::shortExceptionMessage(e));
        return;
    }

    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / m_options.max_rate_hz));
    auto next_draw = Clock::now();
    while (true)
    {
        std::optional<LiveViewSnapshot> snap;
        slam::IntensityCloud points;
        {
            std::unique_lock<std::mutex> lock(m_mutex);
            m_wake.wait_until(lock, next_draw, [&] { return m_stop; });
            if (!m_stop && !m_pending && m_new_points.empty())
            {
                m_wake.wait_for(
                    lock, std::chrono::milliseconds(200),
                    [&] { return m_stop || m_pending || !m_new_points.empty(); });
            }
            if (m_stop)
            {
                break;
            }
            snap.swap(m_pending);
            std::swap(points, m_new_points);
            m_has_pending.store(false);
        }
        if (!win->isOpen())
        {
            m_active.store(false);
            std::fprintf(
                stderr, "%s: the viewer window was closed; the run goes on\n",
                m_options.title.c_str());
            break;
        }
        if (!snap && points.empty())
        {
            continue;
        }
        next_draw = Clock::now() + period;
        std::optional<mrpt::math::TPoint3D> follow;
        {
            win->get3DSceneAndLock();
            appendPoints(*objects.cloud, drawn_points, points, m_options.max_points);
            if (snap)
            {
                follow = showSnapshot(objects, *snap);
            }
            win->unlockAccess3DScene();
        }
        if (follow)
        {
            win->setCameraPointingToPoint(
                static_cast<float>(follow->x), static_cast<float>(follow->y),
                static_cast<float>(follow->z));
        }
        if (snap)
        {
            win->addTextMessage(0.01, 0.02, snap->status, STATUS, font(1.0f, 1.0f, 1.0f));
        }
        win->forceRepaint();
        m_drawn.fetch_add(snap ? 1 : 0);
        m_shown.store(true);
    }
    win.reset();
}

}  // namespace emslam::apps
