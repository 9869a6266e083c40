// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/MapperReport.h>
#include <emslam/apps/SvgPlot.h>
#include <emslam/io/AtomicTextFile.h>

#include <algorithm>
#include <cctype>
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
    if (!d.online.empty())
    {
        t.push_back({&d.online, "online (causal)", ONLINE_COLOUR, "2,3"});
    }
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
    plot.axes(rx.padded(0.0, 1.0), ry, "cumulative attempt", "energy [nats]", false, true);
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
std::string timePlot(const std::vector<slam::FrameRecord>& frames)
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
    plot.axes(
        rx.padded(0.0, 1.0), Range{0.0, ry.padded(0.0, 1.0).hi * 1.05}, "frame", "time [ms]", false,
        true);
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
    plot.axes(rx, ry.padded(0.05, 2.0), "rectification", "attempts", true, true);
    plot.boxes(up, "#2ca02c");
    plot.boxes(down, "#d62728");
    plot.legend(
        {{"successes", "#2ca02c", "", Swatch::Box}, {"failures", "#d62728", "", Swatch::Box}});
    return plot.str();
}

const char* const NO_GT = "no ground truth: run the mapper with --gt";

/** One curve per estimate that has metrics against the ground truth. */
struct ErrorCurve
{
    const eval::TrajectoryMetrics* metrics;
    std::string name, colour;
};

std::vector<ErrorCurve> errorCurves(const MapperReportData& d)
{
    std::vector<ErrorCurve> c;
    if (d.egomotion_vs_gt)
    {
        c.push_back({&*d.egomotion_vs_gt, "egomotion", EGO_COLOUR});
    }
    if (d.slam_vs_gt)
    {
        c.push_back({&*d.slam_vs_gt, "SLAM", SLAM_COLOUR});
    }
    return c;
}

/** KITTI's "error over path length": the drift of each segment length, as
 * translation [%] or rotation [deg/m]. */
std::string segmentErrorPlot(const MapperReportData& d, bool rotation)
{
    SvgPlot plot(
        rotation ? "plot-error-distance-rotation" : "plot-error-distance",
        rotation ? "Rotation error over distance travelled (segments)"
                 : "Translation error over distance travelled (segments)",
        200);
    const auto curves = errorCurves(d);
    std::vector<std::pair<Points, const ErrorCurve*>> drawn;
    Range rx, ry;
    for (const auto& c : curves)
    {
        Points p;
        for (const auto& s : c.metrics->segment_errors)
        {
            const double y = rotation ? s.r_err_deg_per_m : s.t_err_percent;
            if (s.segments > 0 && std::isfinite(y))
            {
                p.push_back({s.length_m, y});
                rx.add(s.length_m);
                ry.add(y);
            }
        }
        drawn.emplace_back(p, &c);
    }
    if (curves.empty() || ry.empty())
    {
        plot.message(curves.empty() ? NO_GT : "the path is too short for any segment");
        return plot.str();
    }
    ry.add(0.0);
    plot.axes(
        rx.padded(0.05, 1.0), Range{0.0, ry.padded(0.0, 1e-6).hi * 1.1}, "segment length [m]",
        rotation ? "rotation error [deg/m]" : "translation error [%]");
    std::vector<LegendItem> legend;
    for (const auto& [p, c] : drawn)
    {
        plot.polyline(p, c->colour);
        for (const auto& q : p)
        {
            plot.marker(q, c->colour, false, 3);
        }
        legend.push_back({c->name, c->colour, ""});
    }
    plot.legend(legend);
    return plot.str();
}

/** Position error after alignment at every paired pose. */
std::string errorOverTimePlot(const MapperReportData& d)
{
    SvgPlot plot("plot-error-time", "Position error over time (after alignment)", 200);
    const auto curves = errorCurves(d);
    std::vector<std::pair<Points, const ErrorCurve*>> drawn;
    Range rx, ry;
    for (const auto& c : curves)
    {
        Points p;
        const auto& m = *c.metrics;
        for (std::size_t i = 0; i < std::min(m.error_time_s.size(), m.position_error_m.size()); ++i)
        {
            p.push_back({m.error_time_s[i], m.position_error_m[i]});
            rx.add(p.back().x);
            ry.add(p.back().y);
        }
        drawn.emplace_back(bucketExtremes(p, MAX_POINTS / 2, false), &c);
    }
    if (curves.empty() || rx.empty())
    {
        plot.message(curves.empty() ? NO_GT : "no pose paired with the ground truth");
        return plot.str();
    }
    ry.add(0.0);
    plot.axes(
        rx.padded(0.0, 1.0), Range{0.0, ry.padded(0.0, 1e-3).hi * 1.1}, "time [s]",
        "position error [m]");
    std::vector<LegendItem> legend;
    for (const auto& [p, c] : drawn)
    {
        plot.polyline(p, c->colour);
        legend.push_back({c->name, c->colour, ""});
    }
    plot.legend(legend);
    return plot.str();
}

/** Per-frame counts against the frame index, one curve per selected field. */
std::string perFramePlot(
    const std::vector<slam::FrameRecord>& frames,
    const std::string& id,
    const std::string& title,
    const std::string& y_label,
    const std::vector<std::pair<std::size_t slam::FrameRecord::*, LegendItem>>& fields)
{
    SvgPlot plot(id, title, 200);
    if (frames.empty())
    {
        plot.message("no frames were processed");
        return plot.str();
    }
    Range rx, ry{0.0, 1.0};
    std::vector<Points> curves(fields.size());
    for (const auto& f : frames)
    {
        const double x = static_cast<double>(f.index);
        rx.add(x);
        for (std::size_t k = 0; k < fields.size(); ++k)
        {
            curves[k].push_back({x, static_cast<double>(f.*(fields[k].first))});
            ry.add(curves[k].back().y);
        }
    }
    plot.axes(rx.padded(0.0, 1.0), Range{0.0, ry.hi * 1.1}, "frame", y_label, false, true);
    std::vector<LegendItem> legend;
    for (std::size_t k = 0; k < fields.size(); ++k)
    {
        plot.polyline(bucketExtremes(curves[k], MAX_POINTS / 2, true), fields[k].second.colour);
        legend.push_back(fields[k].second);
    }
    plot.legend(legend);
    return plot.str();
}

std::string matchesPlot(const std::vector<slam::FrameRecord>& frames)
{
    return perFramePlot(
        frames, "plot-matches", "Matches per frame: before LWO and LWO inliers", "matches",
        {{&slam::FrameRecord::initial_matches, {"matches before LWO", "#ff7f0e", ""}},
         {&slam::FrameRecord::final_matches, {"LWO inliers (after LWO)", "#1f77b4", ""}}});
}

std::string pointsPlot(const std::vector<slam::FrameRecord>& frames)
{
    return perFramePlot(
        frames, "plot-points", "3D points per frame", "points",
        {{&slam::FrameRecord::points, {"3D points of the frame", "#9467bd", ""}}});
}

/** Energy before minus energy after, one bar per rectification: the
 * cumulative curve rises as the map grows and hides this drop. */
std::string energyDropPlot(const std::vector<emslam::rectify::RectificationStats>& rects)
{
    SvgPlot plot(
        "plot-energy-drop", "Energy drop per rectification (energy before - energy after)", 200);
    if (rects.empty())
    {
        plot.message("no rectification ran");
        return plot.str();
    }
    const std::size_t k = (rects.size() + MAX_BARS - 1) / MAX_BARS;
    std::vector<std::pair<Point, Point>> drops, rises;
    Range ry{0.0, 0.0};
    for (std::size_t i = 0; i < rects.size(); i += k)
    {
        // The largest change of each group, so a lone big drop stays visible.
        double change = 0;
        for (std::size_t j = i; j < std::min(i + k, rects.size()); ++j)
        {
            const double c = rects[j].energy_before - rects[j].energy_after;
            if (std::isfinite(c) && std::abs(c) > std::abs(change))
            {
                change = c;
            }
        }
        const double x = static_cast<double>(i + 1);
        const double w = 0.4 * static_cast<double>(k);
        (change >= 0 ? drops : rises).push_back({{x - w, 0.0}, {x + w, change}});
        ry.add(change);
    }
    const Range rx{0.5, static_cast<double>(rects.size()) + 0.5};
    plot.axes(
        rx, ry.padded(0.05, 1e-6), "rectification", "energy before - after [nats]", false, true);
    plot.boxes(drops, "#2ca02c");
    plot.boxes(rises, "#d62728");
    plot.legend(
        {{"drop (energy lowered)", "#2ca02c", "", Swatch::Box},
         {"rise (energy raised)", "#d62728", "", Swatch::Box}});
    return plot.str();
}

/** The files a mapper run writes, in the order the report lists them. */
const std::vector<std::pair<std::string, std::string>> KNOWN_OUTPUTS = {
    {"trajectory_egomotion.tum", "egomotion trajectory (TUM)"},
    {"trajectory_slam.tum", "SLAM trajectory (TUM), a pose for every frame"},
    {"trajectory_egomotion_kitti.txt", "egomotion trajectory (KITTI 3x4 poses)"},
    {"trajectory_egomotion_times.txt", "timestamps of the KITTI egomotion poses"},
    {"trajectory_slam_kitti.txt", "SLAM trajectory (KITTI 3x4 poses)"},
    {"trajectory_slam_times.txt", "timestamps of the KITTI SLAM poses"},
    {"keyframes.txt", "the keyframes (accepted frames) of the SLAM trajectory"},
    {"loop_closures.txt", "the loops closed ([LoopCloser]): registered frame pairs"},
    {"map.ply", "map point cloud (PLY)"},
    {"map.3Dscene", "map and trajectories for SceneViewer3D"},
    {"map_top.png", "top view of the map"},
    {"map_grid.gridmap", "2D occupancy grid (MRPT COccupancyGridMap2D, gzip-serialized)"},
    {"map_grid.png", "the occupancy grid: free white, occupied black, unknown grey"},
    {"entropy_map.bin", "serialized CEntropyVoxelMap (emslam-mapview opens it)"},
    {"entropy_map.3Dscene", "the entropy voxels for SceneViewer3D"},
    {"stats.csv", "per-frame and per-rectification statistics"},
    {"summary.json", "summary figures"},
    {"effective.ini", "every parameter this run used"},
};

/** A file name usable in href / src: bytes outside [A-Za-z0-9._~-] percent-encoded. */
std::string urlPath(const std::string& name)
{
    std::string out;
    for (const unsigned char c : name)
    {
        if (std::isalnum(c) || c == '.' || c == '_' || c == '-' || c == '~')
        {
            out += static_cast<char>(c);
        }
        else
        {
            char buf[4];
            std::snprintf(buf, sizeof(buf), "%%%02X", c);
            out += buf;
        }
    }
    return out;
}

/** Links to the files in the report's folder: the known outputs first, then
 * any other file (hidden and unfinished .partial files left out). */
std::string outputLinks(const std::filesystem::path& folder, const std::string& report_name)
{
    std::vector<std::string> others;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(folder, ec))
    {
        const std::string name = e.path().filename().string();
        const bool known = std::any_of(
            KNOWN_OUTPUTS.begin(), KNOWN_OUTPUTS.end(),
            [&](const auto& k) { return k.first == name; });
        if (!known && name != report_name && name.front() != '.' &&
            e.path().extension() != ".partial" && e.is_regular_file(ec))
        {
            others.push_back(name);
        }
    }
    std::sort(others.begin(), others.end());
    std::ostringstream s;
    s << "<ul id=\"outputs\">\n";
    std::size_t listed = 0;
    const auto item = [&](const std::string& name, const std::string& what)
    {
        s << "<li><a href=\"" << escapeHtml(urlPath(name)) << "\">" << escapeHtml(name) << "</a>"
          << (what.empty() ? "" : ": " + escapeHtml(what)) << "</li>\n";
        ++listed;
    };
    for (const auto& [name, what] : KNOWN_OUTPUTS)
    {
        if (std::filesystem::is_regular_file(folder / name, ec))
        {
            item(name, what);
        }
    }
    for (const auto& name : others)
    {
        item(name, "");
    }
    if (listed == 0)
    {
        s << "<li>no other file in this folder</li>\n";
    }
    s << "</ul>\n";
    return s.str();
}

/** The map picture when it exists next to the report, a note otherwise. */
std::string mapPicture(const std::filesystem::path& folder, const std::string& image)
{
    std::error_code ec;
    if (image.empty() || !std::filesystem::is_regular_file(folder / image, ec))
    {
        return "<p id=\"map-missing\">no map picture" +
               (image.empty() ? std::string() : " (" + escapeHtml(image) + ")") +
               " in this folder</p>\n";
    }
    return "<img id=\"map-top\" src=\"" + escapeHtml(urlPath(image)) +
           "\" alt=\"Top view of the map and the trajectories (" + escapeHtml(image) + ")\">\n";
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
#map-top{display:block;max-width:800px;width:100%;height:auto;border:1px solid #ccc}
svg text{font-family:sans-serif;fill:#222}svg .ttl{font-size:14px;font-weight:bold}
svg .msg{font-size:16px;fill:#888}svg .grid{stroke:#e3e3e3;stroke-width:1}
svg .frame{fill:none;stroke:#888;stroke-width:1}
)";

std::string reportHtml(const MapperReportData& d, const std::filesystem::path& file)
{
    const std::filesystem::path folder =
        file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
    const std::string title = escapeHtml(d.title.empty() ? "emslam mapper" : d.title);
    std::ostringstream s;
    s << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << title
      << " - emslam report</title>\n<style>\n"
      << CSS << "</style>\n</head>\n<body>\n<h1>emslam mapper report: " << title << "</h1>\n"
      << "<h2>Summary</h2>\n"
      << summaryTable(d.summary) << "<h2>Map</h2>\n"
      << mapPicture(folder, d.map_image) << "<h2>Trajectories</h2>\n"
      << topView(d) << sideView(d) << "<h2>Error against the ground truth</h2>\n"
      << segmentErrorPlot(d, false) << segmentErrorPlot(d, true) << errorOverTimePlot(d)
      << "<h2>Front-end per frame</h2>\n"
      << matchesPlot(d.frames) << pointsPlot(d.frames) << "<h2>Rectification</h2>\n"
      << energyDropPlot(d.rectifications) << energyPlot(d.rectifications)
      << attemptsPlot(d.rectifications) << "<h2>Timing</h2>\n"
      << timePlot(d.frames) << "<h2>Output files</h2>\n"
      << outputLinks(folder, file.filename().string()) << "</body>\n</html>\n";
    return s.str();
}

}  // namespace

void writeMapperReport(const std::string& file, const MapperReportData& data)
{
    io::writeTextAtomically(file, reportHtml(data, std::filesystem::path(file)));
}

}  // namespace emslam::apps
