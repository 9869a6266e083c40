// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/MapperReport.h>

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
/** Above this many points a curve is decimated: keeps the file small. */
constexpr std::size_t MAX_POINTS = 5000;
/** Above this many rectifications the bars and start dots are grouped. */
constexpr std::size_t MAX_BARS = 1000;

constexpr double SVG_WIDTH = 800;
constexpr double MARGIN_LEFT = 76, MARGIN_RIGHT = 20, MARGIN_TOP = 56, MARGIN_BOTTOM = 52;
constexpr double PLOT_WIDTH = SVG_WIDTH - MARGIN_LEFT - MARGIN_RIGHT;

const char* const EGO_COLOUR = "#d62728";
const char* const SLAM_COLOUR = "#2ca02c";
const char* const GT_COLOUR = "#000000";

struct Point
{
    double x, y;
};
using Points = std::vector<Point>;

std::string escapeHtml(const std::string& s)
{
    std::string out;
    out.reserve(s.size());
    for (const char c : s)
    {
        switch (c)
        {
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '&':
                out += "&amp;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&#39;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

/** An SVG coordinate with at most 2 decimals; never "nan" or "inf". */
std::string fmt(double v)
{
    if (!std::isfinite(v))
    {
        v = 0.0;
    }
    char buf[48];
    std::snprintf(buf, sizeof(buf), "%.2f", std::clamp(v, -1e9, 1e9));
    std::string s(buf);
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.')
    {
        s.pop_back();
    }
    return s == "-0" ? "0" : s;
}

/** A tick label with as many decimals as the tick step needs. */
std::string tickLabel(double v, double step)
{
    char buf[48];
    if (std::abs(v) >= 1e6 || step < 1e-4)
    {
        std::snprintf(buf, sizeof(buf), "%.4g", v);
    }
    else
    {
        const int decimals = std::clamp(static_cast<int>(-std::floor(std::log10(step))), 0, 6);
        std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
    }
    const std::string s(buf);
    return s.find_first_not_of("-0.") == std::string::npos ? "0" : s;
}

/** A data interval; empty until a finite value is added. */
struct Range
{
    double lo{std::numeric_limits<double>::infinity()};
    double hi{-std::numeric_limits<double>::infinity()};

    void add(double v)
    {
        if (std::isfinite(v))
        {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    bool empty() const { return !(lo <= hi); }
    double span() const { return hi - lo; }
    double mid() const { return 0.5 * (lo + hi); }

    /** Widened by `frac` of its span on each side and to at least
     * `min_span`, so equal values still give a drawable interval. */
    Range padded(double frac, double min_span) const
    {
        Range r = empty() ? Range{0.0, 0.0} : *this;
        const double m = r.span() * frac;
        r.lo -= m;
        r.hi += m;
        if (!(r.span() >= min_span))
        {
            const double c = r.mid();
            r = Range{c - 0.5 * min_span, c + 0.5 * min_span};
        }
        return r;
    }
};

/** About 6 round (1, 2, 5 x 10^k) tick values inside `r`. */
std::vector<double> niceTicks(const Range& r, double& step)
{
    const double raw = r.span() / 6.0;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double norm = raw / mag;
    step = (norm < 1.5 ? 1.0 : norm < 3.0 ? 2.0 : norm < 7.0 ? 5.0 : 10.0) * mag;
    std::vector<double> ticks;
    if (!std::isfinite(step) || step <= 0)
    {
        return ticks;
    }
    const double first = std::ceil(r.lo / step) * step;
    for (int i = 0; i < 20 && first + i * step <= r.hi + 1e-9 * step; ++i)
    {
        ticks.push_back(first + i * step);
    }
    return ticks;
}

enum class Swatch
{
    Line,
    Box,  //!< areas and bars
    Dot,
    None  //!< text only
};

struct LegendItem
{
    std::string label, colour, dash;
    Swatch swatch{Swatch::Line};
};

/** Builds one `<svg>` plot: a fixed-width frame, axes in data units and
 * drawing calls that take data coordinates. */
class SvgPlot
{
public:
    SvgPlot(std::string id, std::string title, double plot_height)
        : m_id(std::move(id)), m_title(std::move(title)), m_h(plot_height)
    {
    }

    /** Sets the data ranges and draws grid, ticks and axis labels; `abs_y`
     * labels negative y ticks by their magnitude. */
    void axes(
        const Range& x,
        const Range& y,
        const std::string& x_label,
        const std::string& y_label,
        bool abs_y = false)
    {
        m_x = x;
        m_y = y;
        double step = 0;
        for (const double t : niceTicks(x, step))
        {
            const std::string X = fmt(px(t));
            m_body << "<line class=\"grid\" x1=\"" << X << "\" y1=\"" << fmt(MARGIN_TOP)
                   << "\" x2=\"" << X << "\" y2=\"" << fmt(MARGIN_TOP + m_h) << "\"/>"
                   << "<text x=\"" << X << "\" y=\"" << fmt(MARGIN_TOP + m_h + 16)
                   << "\" text-anchor=\"middle\">" << tickLabel(t, step) << "</text>\n";
        }
        for (const double t : niceTicks(y, step))
        {
            const std::string Y = fmt(py(t));
            m_body << "<line class=\"grid\" x1=\"" << fmt(MARGIN_LEFT) << "\" y1=\"" << Y
                   << "\" x2=\"" << fmt(MARGIN_LEFT + PLOT_WIDTH) << "\" y2=\"" << Y << "\"/>"
                   << "<text x=\"" << fmt(MARGIN_LEFT - 6) << "\" y=\"" << fmt(py(t) + 4)
                   << "\" text-anchor=\"end\">" << tickLabel(abs_y ? std::abs(t) : t, step)
                   << "</text>\n";
        }
        m_body << "<text x=\"" << fmt(MARGIN_LEFT + PLOT_WIDTH / 2) << "\" y=\""
               << fmt(MARGIN_TOP + m_h + 40) << "\" text-anchor=\"middle\">" << escapeHtml(x_label)
               << "</text>\n<text transform=\"translate(16," << fmt(MARGIN_TOP + m_h / 2)
               << ") rotate(-90)\" text-anchor=\"middle\">" << escapeHtml(y_label) << "</text>\n";
    }

    void polyline(const Points& p, const std::string& colour, const std::string& dash = "")
    {
        m_body << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.5\"";
        if (!dash.empty())
        {
            m_body << " stroke-dasharray=\"" << dash << "\"";
        }
        m_body << " points=\"";
        for (const auto& q : p)
        {
            m_body << fmt(px(q.x)) << ',' << fmt(py(q.y)) << ' ';
        }
        m_body << "\"/>\n";
    }

    /** The region between the curve and y = `base`. */
    void area(const Points& p, double base, const std::string& colour)
    {
        if (p.empty())
        {
            return;
        }
        m_body << "<path fill=\"" << colour << "\" fill-opacity=\"0.35\" stroke=\"" << colour
               << "\" stroke-width=\"1\" d=\"M" << fmt(px(p.front().x)) << ' ' << fmt(py(base));
        for (const auto& q : p)
        {
            m_body << 'L' << fmt(px(q.x)) << ' ' << fmt(py(q.y));
        }
        m_body << 'L' << fmt(px(p.back().x)) << ' ' << fmt(py(base)) << "Z\"/>\n";
    }

    void marker(const Point& p, const std::string& colour, bool square, double r = 4)
    {
        const std::string X = fmt(px(p.x) - (square ? r : 0)), Y = fmt(py(p.y) - (square ? r : 0));
        if (square)
        {
            m_body << "<rect x=\"" << X << "\" y=\"" << Y << "\" width=\"" << fmt(2 * r)
                   << "\" height=\"" << fmt(2 * r) << "\"";
        }
        else
        {
            m_body << "<circle cx=\"" << X << "\" cy=\"" << Y << "\" r=\"" << fmt(r) << "\"";
        }
        m_body << " fill=\"white\" stroke=\"" << colour << "\" stroke-width=\"1.5\"/>\n";
    }

    /** Boxes [x0, x1] x [y0, y1] as one path: far smaller than one rect each. */
    void boxes(const std::vector<std::pair<Point, Point>>& b, const std::string& colour)
    {
        m_body << "<path fill=\"" << colour << "\" d=\"";
        for (const auto& [p0, p1] : b)
        {
            m_body << 'M' << fmt(px(p0.x)) << ' ' << fmt(py(p0.y)) << 'H' << fmt(px(p1.x)) << 'V'
                   << fmt(py(p1.y)) << 'H' << fmt(px(p0.x)) << 'Z';
        }
        m_body << "\"/>\n";
    }

    /** One row of legend entries between the title and the plot area. */
    void legend(const std::vector<LegendItem>& items)
    {
        double x = MARGIN_LEFT;
        for (const auto& it : items)
        {
            if (it.swatch == Swatch::Box)
            {
                m_body << "<rect x=\"" << fmt(x) << "\" y=\"34\" width=\"20\" height=\"10\" fill=\""
                       << it.colour << "\"/>";
            }
            else if (it.swatch == Swatch::Dot)
            {
                m_body << "<circle cx=\"" << fmt(x + 10)
                       << "\" cy=\"39\" r=\"3\" fill=\"white\" stroke=\"" << it.colour
                       << "\" stroke-width=\"1.5\"/>";
            }
            else if (it.swatch == Swatch::Line)
            {
                m_body << "<line x1=\"" << fmt(x) << "\" y1=\"39\" x2=\"" << fmt(x + 20)
                       << "\" y2=\"39\" stroke=\"" << it.colour << "\" stroke-width=\"2\""
                       << (it.dash.empty() ? "" : " stroke-dasharray=\"" + it.dash + "\"") << "/>";
            }
            m_body << "<text x=\"" << fmt(x + 26) << "\" y=\"43\">" << escapeHtml(it.label)
                   << "</text>\n";
            x += 40 + 7.0 * static_cast<double>(it.label.size());
        }
    }

    /** A centred note, for plots without data. */
    void message(const std::string& text)
    {
        m_body << "<text class=\"msg\" x=\"" << fmt(MARGIN_LEFT + PLOT_WIDTH / 2) << "\" y=\""
               << fmt(MARGIN_TOP + m_h / 2) << "\" text-anchor=\"middle\">" << escapeHtml(text)
               << "</text>\n";
    }

    std::string str() const
    {
        const double H = MARGIN_TOP + m_h + MARGIN_BOTTOM;
        std::ostringstream s;
        s << "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" << m_id << "\" width=\""
          << fmt(SVG_WIDTH) << "\" height=\"" << fmt(H) << "\" viewBox=\"0 0 " << fmt(SVG_WIDTH)
          << ' ' << fmt(H) << "\" role=\"img\">\n<title>" << escapeHtml(m_title)
          << "</title>\n<text class=\"ttl\" x=\"" << fmt(MARGIN_LEFT) << "\" y=\"20\">"
          << escapeHtml(m_title) << "</text>\n<rect class=\"frame\" x=\"" << fmt(MARGIN_LEFT)
          << "\" y=\"" << fmt(MARGIN_TOP) << "\" width=\"" << fmt(PLOT_WIDTH) << "\" height=\""
          << fmt(m_h) << "\"/>\n"
          << m_body.str() << "</svg>\n";
        return s.str();
    }

private:
    double px(double x) const { return MARGIN_LEFT + (x - m_x.lo) / m_x.span() * PLOT_WIDTH; }
    double py(double y) const { return MARGIN_TOP + (m_y.hi - y) / m_y.span() * m_h; }

    std::string m_id, m_title;
    double m_h;
    Range m_x{0.0, 1.0}, m_y{0.0, 1.0};
    std::ostringstream m_body;
};

/** Every k-th point plus the last one, at most about `max_n`. */
Points decimate(const Points& p, std::size_t max_n)
{
    if (p.size() <= max_n)
    {
        return p;
    }
    const std::size_t k = (p.size() + max_n - 1) / max_n;
    Points out;
    for (std::size_t i = 0; i < p.size(); i += k)
    {
        out.push_back(p[i]);
    }
    if (out.back().x != p.back().x || out.back().y != p.back().y)
    {
        out.push_back(p.back());
    }
    return out;
}

/** Groups of consecutive points reduced to their minimum and maximum (or
 * only the maximum), so peaks survive the decimation. */
Points bucketExtremes(const Points& p, std::size_t max_n, bool keep_min)
{
    const std::size_t per = keep_min ? 2 : 1;
    if (p.size() <= max_n)
    {
        return p;
    }
    const std::size_t k = (p.size() * per + max_n - 1) / max_n;
    Points out;
    for (std::size_t i = 0; i < p.size(); i += k)
    {
        const auto end = p.begin() + static_cast<std::ptrdiff_t>(std::min(i + k, p.size()));
        const auto [lo, hi] = std::minmax_element(
            p.begin() + static_cast<std::ptrdiff_t>(i), end,
            [](const Point& a, const Point& b) { return a.y < b.y; });
        if (keep_min && lo < hi)
        {
            out.push_back(*lo);
        }
        out.push_back(*hi);
        if (keep_min && lo > hi)
        {
            out.push_back(*lo);
        }
    }
    return out;
}

/** Sizes the plot height (within [h_min, h_max]) and widens the ranges so
 * that one metre has the same length on both axes. */
double equalAspect(Range& x, Range& y, double h_min, double h_max)
{
    const double h = std::clamp(y.span() / x.span() * PLOT_WIDTH, h_min, h_max);
    const double scale = std::min(PLOT_WIDTH / x.span(), h / y.span());  // px per metre
    const double cx = x.mid(), cy = y.mid();
    x = Range{cx - 0.5 * PLOT_WIDTH / scale, cx + 0.5 * PLOT_WIDTH / scale};
    y = Range{cy - 0.5 * h / scale, cy + 0.5 * h / scale};
    return h;
}

struct Track
{
    const emslam::stereo::TumTrajectory* traj;
    std::string name, colour, dash;
};

std::vector<Track> tracks(const MapperReportData& d)
{
    std::vector<Track> t{
        {&d.egomotion, "egomotion", EGO_COLOUR, ""}, {&d.slam, "SLAM", SLAM_COLOUR, ""}};
    if (!d.ground_truth.empty())
    {
        t.push_back({&d.ground_truth, "ground truth", GT_COLOUR, "6,4"});
    }
    return t;
}

using Projection = std::function<Point(const mrpt::poses::CPose3D&)>;

Points project(const emslam::stereo::TumTrajectory& traj, const Projection& proj)
{
    Points p;
    for (const auto& tp : traj.poses)
    {
        const Point q = proj(tp.pose);
        if (std::isfinite(q.x) && std::isfinite(q.y))
        {
            p.push_back(q);
        }
    }
    return decimate(p, MAX_POINTS);
}

/** The trajectories in one plane, equal aspect, start circle and end square. */
std::string trajectoryPlot(
    const MapperReportData& d,
    const std::string& id,
    const std::string& title,
    const Projection& proj,
    const std::string& x_label,
    const std::string& y_label,
    double h_min,
    double h_max)
{
    std::vector<std::pair<Points, const Track*>> curves;
    const auto ts = tracks(d);
    Range rx, ry;
    for (const auto& t : ts)
    {
        curves.emplace_back(project(*t.traj, proj), &t);
        for (const auto& q : curves.back().first)
        {
            rx.add(q.x);
            ry.add(q.y);
        }
    }
    if (rx.empty())
    {
        SvgPlot plot(id, title, h_min);
        plot.message("no data: the trajectories are empty");
        return plot.str();
    }
    rx = rx.padded(0.05, 2.0);  // at least 2 m: a flat or still track is no degenerate line
    ry = ry.padded(0.05, 2.0);
    SvgPlot plot(id, title, equalAspect(rx, ry, h_min, h_max));
    plot.axes(rx, ry, x_label, y_label);
    std::vector<LegendItem> legend;
    for (const auto& [pts, t] : curves)
    {
        if (pts.empty())
        {
            continue;
        }
        plot.polyline(pts, t->colour, t->dash);
        plot.marker(pts.front(), t->colour, false);
        plot.marker(pts.back(), t->colour, true);
        legend.push_back({t->name, t->colour, t->dash});
    }
    legend.push_back({"\u25cb start  \u25a1 end", "", "", Swatch::None});
    plot.legend(legend);
    return plot.str();
}

std::string topView(const MapperReportData& d)
{
    return trajectoryPlot(
        d, "plot-top", "Top view (X-Z plane)",
        [](const mrpt::poses::CPose3D& p) {
            return Point{p.x(), p.z()};
        },
        "x [m]", "z [m]", 240, 480);
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
        d, "plot-side", along_z ? "Side view (Z-Y plane)" : "Side view (X-Y plane)", proj,
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

/** Writes to a temporary file renamed at the end: a reader never sees half a report. */
void writeAtomically(const std::string& file, const std::string& text)
{
    const std::string tmp = file + ".partial";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        out.close();
        if (!out)
        {
            std::error_code ignored;
            std::filesystem::remove(tmp, ignored);
            throw std::runtime_error("cannot write the report '" + file + "'");
        }
    }
    std::error_code ec, ignored;
    std::filesystem::rename(tmp, file, ec);
    if (ec)
    {
        std::filesystem::remove(tmp, ignored);
        throw std::runtime_error("cannot write the report '" + file + "': " + ec.message());
    }
}
}  // namespace

void writeMapperReport(const std::string& file, const MapperReportData& data)
{
    writeAtomically(file, reportHtml(data));
}

}  // namespace emslam::apps
