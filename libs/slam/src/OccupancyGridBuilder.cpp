// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/OccupancyGridBuilder.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace emslam::slam
{
namespace
{
/** Cell values of MRPT's grid: the probability of being free. */
constexpr float OCCUPIED = 0.05f;
constexpr float FREE = 0.95f;
constexpr double MAX_CELLS = 1e8;
}  // namespace

namespace
{
/** Every key of the section, once for load and save. */
void visit(OccupancyGridBuilder::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("cell_size", p.cell_size, "[m] map_grid cell (0: no grid)");
    v.field("min_height", p.min_height, "[m] above the first camera: lowest obstacle");
    v.field("max_height", p.max_height, "[m] above the first camera: highest obstacle");
    v.field("min_points", p.min_points, "map points an occupied cell needs");
    v.field("fov_deg", p.fov_deg, "[deg] horizontal view a keyframe sees free space in");
    v.field("max_range", p.max_range, "[m] reach of a keyframe's free-space rays");
}
}  // namespace

void OccupancyGridBuilder::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void OccupancyGridBuilder::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void OccupancyGridBuilder::TParameters::validate() const
{
    const auto bad = [](const std::string& key, const std::string& why)
    { throw std::invalid_argument("[OccupancyGridBuilder] " + key + ": " + why); };
    if (!(cell_size >= 0) || !std::isfinite(cell_size) || (cell_size > 0 && cell_size < 0.01))
    {
        bad("cell_size", "must be 0 (no grid) or a length >= 0.01 m");
    }
    if (!std::isfinite(min_height) || !std::isfinite(max_height) || !(min_height < max_height))
    {
        bad("max_height", "must be finite and above min_height");
    }
    if (min_points < 1)
    {
        bad("min_points", "must be >= 1");
    }
    if (!(fov_deg > 0 && fov_deg <= 360))
    {
        bad("fov_deg", "must be in (0, 360] deg");
    }
    if (!(max_range > 0) || !std::isfinite(max_range) || max_range > 1000)
    {
        bad("max_range", "must be in (0, 1000] m");
    }
}

OccupancyGridBuilder::OccupancyGridBuilder(const TParameters& p) : m_p(p)
{
    m_p.validate();
}

namespace
{
/** A grid's cells as one array, and what build() learns of each. */
class CellArray
{
public:
    explicit CellArray(const mrpt::maps::COccupancyGridMap2D& grid)
        : m_grid(grid),
          m_nx(static_cast<int>(grid.getSizeX())),
          m_ny(static_cast<int>(grid.getSizeY())),
          m_hits(static_cast<std::size_t>(m_nx) * static_cast<std::size_t>(m_ny), 0),
          m_seen(m_hits.size(), UNSEEN)
    {
    }
    enum Seen : char
    {
        UNSEEN = 0,
        SEEN_THROUGH = 1,
        MET = 2
    };
    /** The cell of grid point (x, y), or -1 outside. */
    long index(double x, double y) const
    {
        const int cx = m_grid.x2idx(x), cy = m_grid.y2idx(y);
        return cx < 0 || cy < 0 || cx >= m_nx || cy >= m_ny ? -1
                                                            : cx + static_cast<long>(cy) * m_nx;
    }
    int& hits(long i) { return m_hits[static_cast<std::size_t>(i)]; }
    char& seen(long i) { return m_seen[static_cast<std::size_t>(i)]; }
    int nx() const { return m_nx; }
    int ny() const { return m_ny; }

private:
    const mrpt::maps::COccupancyGridMap2D& m_grid;
    int m_nx, m_ny;
    std::vector<int> m_hits;
    std::vector<char> m_seen;
};
/** Rays over each keyframe's field of view, half a cell per step, until the
 * first cell dense with points: the surface the ray met. Dense cells no ray
 * reaches lie behind the surfaces seen (stereo depth noise spreads a wall's
 * points along the viewing rays): they stay unseen. Returns the rays cast. */
std::size_t castRays(
    CellArray& cells,
    const OccupancyGridBuilder::TParameters& p,
    const std::vector<emslam::rectify::TimedPose>& keyframes)
{
    const double fov = mrpt::DEG2RAD(p.fov_deg);
    const int rays = 1 + static_cast<int>(std::ceil(fov * p.max_range / p.cell_size));
    const int steps = static_cast<int>(std::ceil(p.max_range / (0.5 * p.cell_size)));
    std::size_t cast = 0;
    for (const auto& k : keyframes)
    {
        const auto o = OccupancyGridBuilder::gridPoint(k.T_world_frame.asTPose().translation());
        // The optical axis (camera +z) in the world, then in the grid.
        const auto R = k.T_world_frame.getRotationMatrix();
        const auto axis = OccupancyGridBuilder::gridPoint({R(0, 2), R(1, 2), R(2, 2)});
        if (std::hypot(axis.x, axis.y) < 0.1)
        {
            continue;  // looking up or down: no horizontal view
        }
        const double heading = std::atan2(axis.y, axis.x);
        for (int r = 0; r < rays; ++r)
        {
            const double a = heading - 0.5 * fov + fov * (rays > 1 ? r / double(rays - 1) : 0.5);
            ++cast;
            for (int s = 0; s <= steps; ++s)
            {
                const double d = 0.5 * p.cell_size * s;
                const long i = cells.index(o.x + d * std::cos(a), o.y + d * std::sin(a));
                if (i < 0)
                {
                    break;
                }
                if (cells.hits(i) >= p.min_points)
                {
                    cells.seen(i) = CellArray::MET;
                    break;
                }
                cells.seen(i) = CellArray::SEEN_THROUGH;
            }
        }
    }
    return cast;
}
}  // namespace

std::vector<mrpt::math::TPoint2D> OccupancyGridBuilder::bandPoints(
    const IntensityCloud& cloud) const
{
    std::vector<mrpt::math::TPoint2D> band;
    for (const auto& p : cloud.points)
    {
        const double h = -static_cast<double>(p.y);
        if (std::isfinite(p.x) && std::isfinite(p.z) && h >= m_p.min_height && h <= m_p.max_height)
        {
            band.push_back(gridPoint(mrpt::math::TPoint3D(p)));
        }
    }
    return band;
}

mrpt::maps::COccupancyGridMap2D OccupancyGridBuilder::emptyGrid(
    const std::vector<mrpt::math::TPoint2D>& band,
    const std::vector<emslam::rectify::TimedPose>& keyframes) const
{
    double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
    const auto extend = [&](const mrpt::math::TPoint2D& q)
    {
        x0 = std::min(x0, q.x);
        x1 = std::max(x1, q.x);
        y0 = std::min(y0, q.y);
        y1 = std::max(y1, q.y);
    };
    for (const auto& q : band)
    {
        extend(q);
    }
    for (const auto& k : keyframes)
    {
        extend(gridPoint(k.T_world_frame.asTPose().translation()));
    }
    if (!(x0 <= x1))
    {
        x0 = y0 = -1;
        x1 = y1 = 1;
    }
    const double cells = ((x1 - x0) / m_p.cell_size + 5) * ((y1 - y0) / m_p.cell_size + 5);
    if (!(cells <= MAX_CELLS))
    {
        throw std::invalid_argument(
            "OccupancyGridBuilder: the map spans " + std::to_string(x1 - x0) + " x " +
            std::to_string(y1 - y0) +
            " m: more than 1e8 cells of [OccupancyGridBuilder] cell_size");
    }
    const double margin = 2 * m_p.cell_size;
    mrpt::maps::COccupancyGridMap2D grid;
    grid.setSize(
        static_cast<float>(x0 - margin), static_cast<float>(x1 + margin),
        static_cast<float>(y0 - margin), static_cast<float>(y1 + margin),
        static_cast<float>(m_p.cell_size), 0.5f);
    return grid;
}

mrpt::maps::COccupancyGridMap2D OccupancyGridBuilder::build(
    const IntensityCloud& cloud, const std::vector<emslam::rectify::TimedPose>& keyframes)
{
    if (m_p.cell_size <= 0)
    {
        throw std::invalid_argument("OccupancyGridBuilder: [OccupancyGridBuilder] cell_size is 0");
    }
    m_stats = {};
    const std::vector<mrpt::math::TPoint2D> band = bandPoints(cloud);
    m_stats.band_points = band.size();
    mrpt::maps::COccupancyGridMap2D grid = emptyGrid(band, keyframes);
    CellArray cells(grid);
    for (const auto& q : band)
    {
        if (const long i = cells.index(q.x, q.y); i >= 0)
        {
            ++cells.hits(i);
        }
    }
    m_stats.rays = castRays(cells, m_p, keyframes);
    for (int cy = 0; cy < cells.ny(); ++cy)
    {
        for (int cx = 0; cx < cells.nx(); ++cx)
        {
            const char seen = cells.seen(cx + static_cast<long>(cy) * cells.nx());
            if (seen == CellArray::MET)
            {
                grid.setCell(cx, cy, OCCUPIED);
                ++m_stats.occupied;
            }
            else if (seen == CellArray::SEEN_THROUGH)
            {
                grid.setCell(cx, cy, FREE);
                ++m_stats.free;
            }
        }
    }
    m_stats.cells = static_cast<std::size_t>(cells.nx()) * static_cast<std::size_t>(cells.ny());
    return grid;
}

}  // namespace emslam::slam
