// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/AtomicTextFile.h>
#include <emslam/apps/MapperReport.h>
#include <emslam/apps/SvgPlot.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace emslam::apps
{
namespace
{
/** Above this many rectifications the bars and start dots are grouped. */
constexpr std::size_t MAX_BARS = 1000;

using namespace emslam::apps::svg;

std::vector<TrajectoryTrack> tracks(const MapperReportData& d)
{
    std::vector<TrajectoryTrack> t{
        {&d.egomotion, "egomotion", EGO_COLOUR, ""}, {&d.slam, "SLAM", SLAM_COLOUR, ""}};
    if (!d.ground_truth.empty())
    {
        t.push_back({&d.ground_truth, "ground truth", GT_COLOUR, "6,4"});
    }
    return t;
}

std::string topView(const MapperReportData& d)
{
    return trajectoryPlot(
        tracks(d), "plot-top", "Top view (X-Z plane)", topViewProjection, "x [m]", "z [m]", 240,
        480);
}

/** Height (-y, so up is up) against whichever of x and z the robot moved
 * along most. */
std::string sideView(const MapperReportData& d)
{
    Range rx, rz;
    for (const auto& t : tracks(d))
    {
        for (const auto& tp : t.traj->poses)
        {
            rx.add(tp.pose.x());
            rz.add(tp.pose.z());
        }
    }
    const bool along_z = !rz.empty() && (rx.empty() || rz.span() > rx.span());
    const Projection proj = [along_z](const mrpt::poses::CPose3D& p) {
        return Point{along_z ? p.z() : p.x(), -p.y()};
    };
    return trajectoryPlot(
        tracks(d), "plot-side", along_z ? "Side view (Z-Y plane)" : "Side view (X-Y plane)", proj,
        along_z ? "z [m]" : "x [m]", "height -y [m]", 160, 280);
}

/** Energy after every attempt, all rectifications end to end. */
std::string energyPlot(const std::vector<emslam::rectify::RectificationStats>& rects)
{
    SvgPlot plot("plot-energy", "Energy over the rectification attempts", 240);
    if (rects.empty())
    {
        plot.message("no rectification ran");
        return plot.str();
    }
    Points curve, starts;
    double offset = 0;
    for (const auto& r : rects)
    {
        if (r.energy_trace.empty())
        {
            // No trace kept: the energies before and after stand for it.
            starts.push_back({offset, r.energy_before});
            curve.push_back(starts.back());
            curve.push_back({offset + static_cast<double>(r.attempts), r.energy_after});
            offset += static_cast<double>(r.attempts);
            continue;
        }
        starts.push_back({offset, r.energy_trace.front()});
        for (const float e : r.energy_trace)
        {
            curve.push_back({offset++, e});
        }
    }
    const auto bad = [](const Point& q) { return !std::isfinite(q.x) || !std::isfinite(q.y); };
    curve.erase(std::remove_if(curve.begin(), curve.end(), bad), curve.end());
    starts.erase(std::remove_if(starts.begin(), starts.end(), bad), starts.end());
    Range rx, ry;
    for (const auto& q : curve)
    {
        rx.add(q.x);
        ry.add(q.y);
    }
    if (ry.empty())
    {
        plot.message("no finite energy recorded");
        return plot.str();
    }
    ry = ry.padded(0.05, std::max(1e-9, 1e-3 * std::max(std::abs(ry.lo), std::abs(ry.hi))));
    plot.axes(rx.padded(0.0, 1.0), ry, "cumulative attempt", "energy [nats]");
    plot.polyline(bucketExtremes(curve, MAX_POINTS, true), "#1f77b4");
    const std::size_t k = (starts.size() + MAX_BARS - 1) / MAX_BARS;
    for (std::size_t i = 0; i < starts.size(); i += k)
    {
        plot.marker(starts[i], "#ff7f0e", false, 3);
    }
    plot.legend(
        {{"energy after each attempt", "#1f77b4", ""},
         {"start of a rectification", "#ff7f0e", "", Swatch::Dot}});
    return plot.str();
}

/** Paper Fig. 17: front-end time per frame and the rectification peaks. */
std::string timePlot(const std::vector<MapperFrameRecord>& frames)
{
    SvgPlot plot("plot-time", "Time per frame", 240);
    if (frames.empty())
    {
        plot.message("no frames were processed");
        return plot.str();
    }
    Points front, rect;
    Range rx, ry;
    for (const auto& f : frames)
    {
        const double x = static_cast<double>(f.index);
        front.push_back({x, f.ms_stereo + f.ms_egomotion});
        rect.push_back({x, f.ms_rectification});
        rx.add(x);
        ry.add(front.back().y);
        ry.add(f.ms_rectification);
    }
    ry.add(0.0);
    plot.axes(rx.padded(0.0, 1.0), Range{0.0, ry.padded(0.0, 1.0).hi * 1.05}, "frame", "time [ms]");
    plot.area(bucketExtremes(front, MAX_POINTS / 2, false), 0.0, "#1f77b4");
    plot.polyline(bucketExtremes(rect, MAX_POINTS / 2, false), "#d62728");
    plot.legend(
        {{"stereo + egomotion", "#1f77b4", "", Swatch::Box}, {"rectification", "#d62728", ""}});
    return plot.str();
}

/** Paper Fig. 20: successes up, failures down, one bar per rectification
 * (the largest of each group when there are very many). */
std::string attemptsPlot(const std::vector<emslam::rectify::RectificationStats>& rects)
{
    SvgPlot plot("plot-attempts", "Successful and failed attempts per rectification", 220);
    if (rects.empty())
    {
        plot.message("no rectification ran");
        return plot.str();
    }
    const std::size_t k = (rects.size() + MAX_BARS - 1) / MAX_BARS;
    std::vector<std::pair<Point, Point>> up, down;
    Range ry;
    for (std::size_t i = 0; i < rects.size(); i += k)
    {
        double s = 0, f = 0;
        for (std::size_t j = i; j < std::min(i + k, rects.size()); ++j)
        {
            s = std::max(s, static_cast<double>(rects[j].successes));
            f = std::max(f, static_cast<double>(rects[j].failures));
        }
        const double x = static_cast<double>(i + 1);
        const double w = 0.4 * static_cast<double>(k);
        up.push_back({{x - w, 0.0}, {x + w, s}});
        down.push_back({{x - w, 0.0}, {x + w, -f}});
        ry.add(s);
        ry.add(-f);
    }
    ry.add(0.0);
    const Range rx{0.5, static_cast<double>(rects.size()) + 0.5};
    plot.axes(rx, ry.padded(0.05, 2.0), "rectification", "attempts", true);
    plot.boxes(up, "#2ca02c");
    plot.boxes(down, "#d62728");
    plot.legend(
        {{"successes", "#2ca02c", "", Swatch::Box}, {"failures", "#d62728", "", Swatch::Box}});
    return plot.str();
}

std::string summaryTable(const std::vector<std::pair<std::string, std::string>>& rows)
{
    std::ostringstream s;
    s << "<table id=\"summary\">\n";
    for (const auto& [name, value] : rows)
    {
        s << "<tr><th>" << escapeHtml(name) << "</th><td>" << escapeHtml(value) << "</td></tr>\n";
    }
    if (rows.empty())
    {
        s << "<tr><td>no summary</td></tr>\n";
    }
    s << "</table>\n";
    return s.str();
}

const char* const CSS = R"(body{font-family:sans-serif;margin:24px;color:#222}
h1{font-size:22px}h2{font-size:17px;margin:20px 0 6px}
table{border-collapse:collapse}th,td{border:1px solid #ccc;padding:3px 10px;text-align:left}
th{background:#f3f3f3;font-weight:normal}
svg{display:block;max-width:100%;height:auto;font-size:12px}
svg text{font-family:sans-serif;fill:#222}svg .ttl{font-size:14px;font-weight:bold}
svg .msg{font-size:16px;fill:#888}svg .grid{stroke:#e3e3e3;stroke-width:1}
svg .frame{fill:none;stroke:#888;stroke-width:1}
)";

std::string reportHtml(const MapperReportData& d)
{
    const std::string title = escapeHtml(d.title.empty() ? "emslam mapper" : d.title);
    std::ostringstream s;
    s << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << title
      << " - emslam report</title>\n<style>\n"
      << CSS << "</style>\n</head>\n<body>\n<h1>emslam mapper report: " << title << "</h1>\n"
      << "<h2>Summary</h2>\n"
      << summaryTable(d.summary) << "<h2>Trajectories</h2>\n"
      << topView(d) << sideView(d) << "<h2>Rectification</h2>\n"
      << energyPlot(d.rectifications) << attemptsPlot(d.rectifications) << "<h2>Timing</h2>\n"
      << timePlot(d.frames) << "</body>\n</html>\n";
    return s.str();
}

}  // namespace

void writeMapperReport(const std::string& file, const MapperReportData& data)
{
    writeTextAtomically(file, reportHtml(data));
}

}  // namespace emslam::apps
