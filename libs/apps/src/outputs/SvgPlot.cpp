// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/SvgPlot.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace emslam::apps::svg
{
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

void Range::add(double v)
{
    if (std::isfinite(v))
    {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
}

Range Range::padded(double frac, double min_span) const
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

std::vector<double> integerTicks(const Range& r, double& step)
{
    std::vector<double> ticks = niceTicks(r, step);
    if (!(step < 1.0))
    {
        return ticks;
    }
    step = 1.0;
    ticks.clear();
    for (double t = std::ceil(r.lo); t <= r.hi + 1e-9 && ticks.size() < 20; t += 1.0)
    {
        ticks.push_back(t);
    }
    return ticks;
}

SvgPlot::SvgPlot(std::string id, std::string title, double plot_height)
    : m_id(std::move(id)), m_title(std::move(title)), m_h(plot_height)
{
}

void SvgPlot::axes(
    const Range& x,
    const Range& y,
    const std::string& x_label,
    const std::string& y_label,
    bool abs_y,
    bool integer_x)
{
    m_x = x;
    m_y = y;
    double step = 0;
    for (const double t : integer_x ? integerTicks(x, step) : niceTicks(x, step))
    {
        const std::string X = fmt(px(t));
        m_body << "<line class=\"grid\" x1=\"" << X << "\" y1=\"" << fmt(MARGIN_TOP) << "\" x2=\""
               << X << "\" y2=\"" << fmt(MARGIN_TOP + m_h) << "\"/>"
               << "<text x=\"" << X << "\" y=\"" << fmt(MARGIN_TOP + m_h + 16)
               << "\" text-anchor=\"middle\">" << tickLabel(t, step) << "</text>\n";
    }
    for (const double t : niceTicks(y, step))
    {
        const std::string Y = fmt(py(t));
        m_body << "<line class=\"grid\" x1=\"" << fmt(MARGIN_LEFT) << "\" y1=\"" << Y << "\" x2=\""
               << fmt(MARGIN_LEFT + PLOT_WIDTH) << "\" y2=\"" << Y << "\"/>"
               << "<text x=\"" << fmt(MARGIN_LEFT - 6) << "\" y=\"" << fmt(py(t) + 4)
               << "\" text-anchor=\"end\">" << tickLabel(abs_y ? std::abs(t) : t, step)
               << "</text>\n";
    }
    m_body << "<text x=\"" << fmt(MARGIN_LEFT + PLOT_WIDTH / 2) << "\" y=\""
           << fmt(MARGIN_TOP + m_h + 40) << "\" text-anchor=\"middle\">" << escapeHtml(x_label)
           << "</text>\n<text transform=\"translate(16," << fmt(MARGIN_TOP + m_h / 2)
           << ") rotate(-90)\" text-anchor=\"middle\">" << escapeHtml(y_label) << "</text>\n";
}

void SvgPlot::polyline(const Points& p, const std::string& colour, const std::string& dash)
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

void SvgPlot::area(const Points& p, double base, const std::string& colour)
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

void SvgPlot::marker(const Point& p, const std::string& colour, bool square, double r)
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

void SvgPlot::boxes(const std::vector<std::pair<Point, Point>>& b, const std::string& colour)
{
    m_body << "<path fill=\"" << colour << "\" d=\"";
    for (const auto& [p0, p1] : b)
    {
        m_body << 'M' << fmt(px(p0.x)) << ' ' << fmt(py(p0.y)) << 'H' << fmt(px(p1.x)) << 'V'
               << fmt(py(p1.y)) << 'H' << fmt(px(p0.x)) << 'Z';
    }
    m_body << "\"/>\n";
}

void SvgPlot::legend(const std::vector<LegendItem>& items)
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

void SvgPlot::message(const std::string& text)
{
    m_body << "<text class=\"msg\" x=\"" << fmt(MARGIN_LEFT + PLOT_WIDTH / 2) << "\" y=\""
           << fmt(MARGIN_TOP + m_h / 2) << "\" text-anchor=\"middle\">" << escapeHtml(text)
           << "</text>\n";
}

std::string SvgPlot::str() const
{
    const double H = MARGIN_TOP + m_h + MARGIN_BOTTOM;
    std::ostringstream s;
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" << m_id << "\" width=\""
      << fmt(SVG_WIDTH) << "\" height=\"" << fmt(H) << "\" viewBox=\"0 0 " << fmt(SVG_WIDTH) << ' '
      << fmt(H) << "\" role=\"img\">\n<title>" << escapeHtml(m_title)
      << "</title>\n<text class=\"ttl\" x=\"" << fmt(MARGIN_LEFT) << "\" y=\"20\">"
      << escapeHtml(m_title) << "</text>\n<rect class=\"frame\" x=\"" << fmt(MARGIN_LEFT)
      << "\" y=\"" << fmt(MARGIN_TOP) << "\" width=\"" << fmt(PLOT_WIDTH) << "\" height=\""
      << fmt(m_h) << "\"/>\n"
      << m_body.str() << "</svg>\n";
    return s.str();
}

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

double equalAspect(Range& x, Range& y, double h_min, double h_max)
{
    const double h = std::clamp(y.span() / x.span() * PLOT_WIDTH, h_min, h_max);
    const double scale = std::min(PLOT_WIDTH / x.span(), h / y.span());  // px per metre
    const double cx = x.mid(), cy = y.mid();
    x = Range{cx - 0.5 * PLOT_WIDTH / scale, cx + 0.5 * PLOT_WIDTH / scale};
    y = Range{cy - 0.5 * h / scale, cy + 0.5 * h / scale};
    return h;
}

namespace
{
Points project(const emslam::io::TumTrajectory& traj, const Projection& proj)
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

}  // namespace

std::string trajectoryPlot(
    const std::vector<TrajectoryTrack>& ts,
    const std::string& id,
    const std::string& title,
    const Projection& proj,
    const std::string& x_label,
    const std::string& y_label,
    double h_min,
    double h_max)
{
    std::vector<std::pair<Points, const TrajectoryTrack*>> curves;
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

Point topViewProjection(const mrpt::poses::CPose3D& p)
{
    return Point{p.x(), p.z()};
}

}  // namespace emslam::apps::svg
