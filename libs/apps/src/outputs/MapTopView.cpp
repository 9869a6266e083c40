// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/MapStyle.h>
#include <emslam/apps/MapTopView.h>
#include <emslam/io/AtomicFile.h>
#include <emslam/io/ImageOutput.h>

#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace emslam::apps
{
namespace
{
mrpt::math::TPoint3D toViewer(const mrpt::math::TPoint3D& p_map)
{
    static const mrpt::poses::CPose3D T = viewerFromCamera();
    return T.composePoint(p_map);
}

cv::Scalar bgr(const TrajectoryStyle& s)
{
    return cv::Scalar(255.0 * s.b, 255.0 * s.g, 255.0 * s.r);
}
/** Extent of a plan in the viewer's x, y [m]. */
struct PlanExtent
{
    double x0{HUGE_VAL}, x1{-HUGE_VAL}, y0{HUGE_VAL}, y1{-HUGE_VAL};
};

/** The trajectories and the cloud's 1st..99th percentiles (stray far
 * points would shrink the plan to a dot); +-1 m when there is nothing. */
PlanExtent planExtent(
    const slam::IntensityCloud& kept, const emslam::io::TumTrajectory* const (&trajectories)[3])
{
    std::vector<double> xs, ys;
    for (const auto& p : kept.points)
    {
        const auto v = toViewer(mrpt::math::TPoint3D(p));
        xs.push_back(v.x);
        ys.push_back(v.y);
    }
    PlanExtent e;
    if (!xs.empty())
    {
        const auto pct = [](std::vector<double> v, double f)
        {
            auto it =
                v.begin() + static_cast<std::ptrdiff_t>(f * static_cast<double>(v.size() - 1));
            std::nth_element(v.begin(), it, v.end());
            return *it;
        };
        e.x0 = pct(xs, 0.01);
        e.x1 = pct(xs, 0.99);
        e.y0 = pct(ys, 0.01);
        e.y1 = pct(ys, 0.99);
    }
    for (const auto* t : trajectories)
    {
        for (std::size_t i = 0; t && i < t->size(); ++i)
        {
            const auto v = toViewer(t->poses[i].pose.asTPose().translation());
            e.x0 = std::min(e.x0, v.x);
            e.x1 = std::max(e.x1, v.x);
            e.y0 = std::min(e.y0, v.y);
            e.y1 = std::max(e.y1, v.y);
        }
    }
    if (e.x0 > e.x1)
    {
        e.x0 = e.y0 = -1.0;
        e.x1 = e.y1 = 1.0;
    }
    return e;
}

/** The points' density on a log scale, grey on white, into view.image. */
void drawDensity(
    MapTopView& view, const slam::IntensityCloud& kept, int rows, int cols, double point_size)
{
    cv::Mat count = cv::Mat::zeros(rows, cols, CV_32F);
    for (const auto& p : kept.points)
    {
        const auto px = view.toPixel(mrpt::math::TPoint3D(p));
        const int u = static_cast<int>(std::floor(px.x)), v = static_cast<int>(std::floor(px.y));
        if (u >= 0 && v >= 0 && u < cols && v < rows)
        {
            count.at<float>(v, u) += 1.0f;
        }
    }
    const int splat = static_cast<int>(std::lround(point_size * view.pixels_per_metre));
    if (splat > 1)
    {
        cv::blur(count, count, cv::Size(splat, splat));
    }
    double max_count = 0;
    cv::minMaxLoc(count, nullptr, &max_count);
    cv::Mat grey(rows, cols, CV_8U, cv::Scalar(255));
    if (max_count > 0)
    {
        cv::Mat logc;
        cv::log(count + 1.0f, logc);
        logc.convertTo(grey, CV_8U, -230.0 / std::log(max_count + 1.0), 255.0);
    }
    cv::cvtColor(grey, view.image, cv::COLOR_GRAY2BGR);
}

using DrawnTrajectories = std::pair<const emslam::io::TumTrajectory*, TrajectoryStyle>[3];

/** The legend of what is drawn, and a scale bar of a round length near a
 * fifth of the image. */
void drawLegend(
    MapTopView& view,
    const MapDrawingContent& c,
    const DrawnTrajectories& drawn,
    bool with_loops,
    int rows,
    int cols)
{
    int row = 18;
    const auto text = [&](const std::string& s, const cv::Scalar& color)
    {
        cv::putText(view.image, s, {8, row}, cv::FONT_HERSHEY_SIMPLEX, 0.45, color, 1, cv::LINE_AA);
        row += 17;
    };
    for (const auto& [t, style] : drawn)
    {
        if (t && t->size() >= 2)
        {
            text(style.label, bgr(style));
        }
    }
    if (with_loops)
    {
        text(LOOP_STYLE.label, bgr(LOOP_STYLE));
    }
    if (c.cloud)
    {
        text(
            std::isinf(c.max_height)
                ? std::string("map points, seen from above (darker: denser)")
                : mrpt::format("map points below %.2f m (darker: denser)", c.max_height),
            cv::Scalar(60, 60, 60));
    }
    const double target = 0.2 * cols / view.pixels_per_metre;
    const double bar_m = std::pow(10.0, std::floor(std::log10(target)));
    const double bar = bar_m * (target / bar_m >= 5 ? 5 : (target / bar_m >= 2 ? 2 : 1));
    const int len = static_cast<int>(std::lround(bar * view.pixels_per_metre));
    const cv::Point a(8, rows - 10), b(8 + len, rows - 10);
    cv::line(view.image, a, b, cv::Scalar(0, 0, 0), 2);
    cv::putText(
        view.image, mrpt::format("%g m", bar), {12 + len, rows - 6}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
        cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}
}  // namespace

cv::Point2d MapTopView::toPixel(const mrpt::math::TPoint3D& p_map) const
{
    const auto v = toViewer(p_map);
    return {(v.x - left_x) * pixels_per_metre, (top_y - v.y) * pixels_per_metre};
}

MapTopView renderTopView(const MapDrawingContent& c, const TopViewOptions& o)
{
    if (o.max_side < 64 || o.margin < 0 || 2 * o.margin >= o.max_side)
    {
        throw std::invalid_argument(mrpt::format(
            "top view: max_side must be >= 64 and margin in [0, max_side/2) (got %d, %d)",
            o.max_side, o.margin));
    }
    const slam::IntensityCloud kept =
        c.cloud ? cutAboveHeight(*c.cloud, c.max_height) : slam::IntensityCloud{};
    const emslam::io::TumTrajectory* const trajectories[] = {c.egomotion, c.slam, c.ground_truth};
    const auto [x0, x1, y0, y1] = planExtent(kept, trajectories);
    const double span = std::max({x1 - x0, y1 - y0, 1.0});
    MapTopView view;
    view.pixels_per_metre = (o.max_side - 2 * o.margin) / span;
    view.left_x = x0 - o.margin / view.pixels_per_metre;
    view.top_y = y1 + o.margin / view.pixels_per_metre;
    const int cols = static_cast<int>(std::ceil((x1 - x0) * view.pixels_per_metre)) + 2 * o.margin;
    const int rows = static_cast<int>(std::ceil((y1 - y0) * view.pixels_per_metre)) + 2 * o.margin;
    drawDensity(view, kept, rows, cols, o.point_size);

    // Trajectories: ground truth first, so the estimates are drawn on top.
    const DrawnTrajectories drawn = {
        {c.ground_truth, GROUND_TRUTH_STYLE}, {c.egomotion, EGOMOTION_STYLE}, {c.slam, SLAM_STYLE}};
    for (const auto& [t, style] : drawn)
    {
        if (!t || t->size() < 2)
        {
            continue;
        }
        std::vector<cv::Point> line;
        for (const auto& p : t->poses)
        {
            const auto px = view.toPixel(p.pose.asTPose().translation());
            line.emplace_back(
                static_cast<int>(std::lround(px.x)), static_cast<int>(std::lround(px.y)));
        }
        cv::polylines(view.image, line, false, bgr(style), 2, cv::LINE_AA);
    }
    const auto pixel = [&](const mrpt::math::TPoint3D& p)
    {
        const auto px = view.toPixel(p);
        return cv::Point(static_cast<int>(std::lround(px.x)), static_cast<int>(std::lround(px.y)));
    };
    const bool with_loops = c.loops && !c.loops->empty();
    if (with_loops)
    {
        for (const auto& [a, b] : *c.loops)
        {
            cv::line(view.image, pixel(a), pixel(b), bgr(LOOP_STYLE), 1, cv::LINE_AA);
        }
    }
    if (o.legend)
    {
        drawLegend(view, c, drawn, with_loops, rows, cols);
    }
    return view;
}

void writeTopView(
    const MapDrawingContent& content, const std::string& file, const TopViewOptions& o)
{
    const MapTopView view = renderTopView(content, o);
    emslam::io::writeFileAtomically(
        file,
        [&](const std::string& partial)
        {
            emslam::io::writeImageFile(partial, view.image, file);
            return true;
        });
}

}  // namespace emslam::apps
