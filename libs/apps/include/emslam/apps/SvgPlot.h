// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TumTrajectory.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

/** Self-contained SVG plots for the HTML reports (mapper, experiments): no
 * script, no network, one `<svg>` element per plot. */
namespace emslam::apps::svg
{
/** Width of every plot [px]; pages scale it with CSS. */
constexpr double SVG_WIDTH = 800;
/** Margins around the plot area [px]: axis labels left and below, title and legend above. */
///@{
constexpr double MARGIN_LEFT = 76, MARGIN_RIGHT = 20, MARGIN_TOP = 56, MARGIN_BOTTOM = 52;
///@}
/** Width of the plot area [px]. */
constexpr double PLOT_WIDTH = SVG_WIDTH - MARGIN_LEFT - MARGIN_RIGHT;

/** Above this many points a curve is decimated: keeps the file small. */
constexpr std::size_t MAX_POINTS = 5000;

/** Colours of the trajectories, the same in every report. */
inline const char* const EGO_COLOUR = "#d62728";
inline const char* const SLAM_COLOUR = "#2ca02c";  //!< SLAM
inline const char* const GT_COLOUR = "#000000";    //!< ground truth
/** The online (causal) trajectory: what the system had while it ran. */
inline const char* const ONLINE_COLOUR = "#1f77b4";

/** A point in data (or, after projection, plot) coordinates. */
struct Point
{
    /** Abscissa and ordinate. */
    ///@{
    double x, y;
    ///@}
};
/** A polyline's points. */
using Points = std::vector<Point>;

/** `s` with the five HTML special characters escaped. */
std::string escapeHtml(const std::string& s);

/** An SVG coordinate with at most 2 decimals; never "nan" or "inf". */
std::string fmt(double v);

/** A tick label with as many decimals as the tick step needs. */
std::string tickLabel(double v, double step);

/** A data interval; empty until a finite value is added. */
struct Range
{
    double lo{std::numeric_limits<double>::infinity()};   //!< lowest value added
    double hi{-std::numeric_limits<double>::infinity()};  //!< highest value added

    /** Widens the interval to `v` (NaN and infinities are ignored). */
    void add(double v);
    /** No finite value added yet. */
    bool empty() const { return !(lo <= hi); }
    /** hi − lo. */
    double span() const { return hi - lo; }
    /** The middle of the interval. */
    double mid() const { return 0.5 * (lo + hi); }

    /** Widened by `frac` of its span on each side and to at least
     * `min_span`, so equal values still give a drawable interval. */
    Range padded(double frac, double min_span) const;
};

/** About 6 round (1, 2, 5 x 10^k) tick values inside `r`; `step` receives
 * their spacing. */
std::vector<double> niceTicks(const Range& r, double& step);

/** As niceTicks(), but the spacing is a whole number (at least 1), so a
 * count axis never shows a fractional tick. */
std::vector<double> integerTicks(const Range& r, double& step);

/** How a legend entry is drawn. */
enum class Swatch
{
    Line,
    Box,  //!< areas and bars
    Dot,
    None  //!< text only
};

/** One legend entry: text, colour, SVG dash pattern and swatch. */
struct LegendItem
{
    /** Legend text, colour and SVG dash pattern ("": solid). */
    ///@{
    std::string label, colour, dash;
    ///@}
    Swatch swatch{Swatch::Line};  //!< how the entry is drawn
};

/** Builds one `<svg>` plot: a fixed-width frame, axes in data units and
 * drawing calls that take data coordinates. */
class SvgPlot
{
public:
    /** An empty plot; `id` is the SVG element's id, `plot_height` the plot area's height [px]. */
    SvgPlot(std::string id, std::string title, double plot_height);

    /** Sets the data ranges and draws grid, ticks and axis labels; `abs_y`
     * labels negative y ticks by their magnitude; `integer_x` keeps the x ticks
     * on whole numbers (counts: frame, rectification, attempt). */
    void axes(
        const Range& x,
        const Range& y,
        const std::string& x_label,
        const std::string& y_label,
        bool abs_y = false,
        bool integer_x = false);

    /** A curve in data coordinates; `dash`: an SVG stroke-dasharray ("": solid). */
    void polyline(const Points& p, const std::string& colour, const std::string& dash = "");
    /** The region between the curve and y = `base`. */
    void area(const Points& p, double base, const std::string& colour);
    /** A circle (or, `square`, a square) of radius `r` [px] at `p`. */
    void marker(const Point& p, const std::string& colour, bool square, double r = 4);
    /** Boxes [x0, x1] x [y0, y1] as one path: far smaller than one rect each. */
    void boxes(const std::vector<std::pair<Point, Point>>& b, const std::string& colour);
    /** One row of legend entries between the title and the plot area. */
    void legend(const std::vector<LegendItem>& items);
    /** A centred note, for plots without data. */
    void message(const std::string& text);

    /** The `<svg>` element: frame, title and everything drawn so far. */
    std::string str() const;

private:
    double px(double x) const { return MARGIN_LEFT + (x - m_x.lo) / m_x.span() * PLOT_WIDTH; }
    double py(double y) const { return MARGIN_TOP + (m_y.hi - y) / m_y.span() * m_h; }

    std::string m_id, m_title;
    double m_h;
    Range m_x{0.0, 1.0}, m_y{0.0, 1.0};
    std::ostringstream m_body;
};

/** Every k-th point plus the last one, at most about `max_n`. */
Points decimate(const Points& p, std::size_t max_n);

/** Groups of consecutive points reduced to their minimum and maximum (or
 * only the maximum), so peaks survive the decimation. */
Points bucketExtremes(const Points& p, std::size_t max_n, bool keep_min);

/** Sizes the plot height (within [h_min, h_max]) and widens the ranges so
 * that one metre has the same length on both axes. */
double equalAspect(Range& x, Range& y, double h_min, double h_max);

/** A trajectory to draw, with its legend name and style. */
struct TrajectoryTrack
{
    const emslam::io::TumTrajectory* traj;  //!< not owned
    /** Legend name, colour and SVG dash pattern. */
    ///@{
    std::string name, colour, dash;
    ///@}
};

/** Maps a pose to the plot plane. */
using Projection = std::function<Point(const mrpt::poses::CPose3D&)>;

/** The trajectories in one plane, equal aspect, a circle at each start and a
 * square at each end; a note instead when every track is empty. */
std::string trajectoryPlot(
    const std::vector<TrajectoryTrack>& tracks,
    const std::string& id,
    const std::string& title,
    const Projection& proj,
    const std::string& x_label,
    const std::string& y_label,
    double h_min,
    double h_max);

/** The X-Z plane (the map's horizontal plane), `x` right and `z` up. */
Point topViewProjection(const mrpt::poses::CPose3D& p);

}  // namespace emslam::apps::svg
