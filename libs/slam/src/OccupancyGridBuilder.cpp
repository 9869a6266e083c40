// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/OccupancyGridBuilder.h>

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

void OccupancyGridBuilder::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    MRPT_LOAD_CONFIG_VAR(cell_size, double, c, s);
    MRPT_LOAD_CONFIG_VAR(min_height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(min_points, int, c, s);
    MRPT_LOAD_CONFIG_VAR(fov_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_range, double, c, s);
    validate();
}

void OccupancyGridBuilder::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    MRPT_SAVE_CONFIG_VAR_COMMENT(cell_size, "[m] map_grid cell (0: no grid)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_height, "[m] above the first camera: lowest obstacle");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_height, "[m] above the first camera: highest obstacle");
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_points, "map points an occupied cell needs");
    MRPT_SAVE_CONFIG_VAR_COMMENT(fov_deg, "[deg] horizontal view a keyframe sees free space in");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_range, "[m] reach of a keyframe's free-space rays");
}

void OccupancyGridBuilder::TParameters::validate() const
{
    const auto bad = [](const std::string& key, const std::string& why)
    { throw std::invalid_argument("[OccupancyGrid] " + key + ": " + why); };
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

mrpt::maps::COccupancyGridMap2D OccupancyGridBuilder::build(
    const IntensityCloud& cloud, const std::vector<emslam::rectify::TimedPose>& keyframes)
{
    if (m_p.cell_size <= 0)
    {
        throw std::invalid_argument("OccupancyGridBuilder: [OccupancyGrid] cell_size is 0");
    }
    m_stats = {};
    std::vector<mrpt::math::TPoint2D> band;
    double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
    const auto extend = [&](const mrpt::math::TPoint2D& q)
    {
        x0 = std::min(x0, q.x);
        x1 = std::max(x1, q.x);
        y0 = std::min(y0, q.y);
        y1 = std::max(y1, q.y);
    };
    for (const auto& p : cloud.points)
    {
        const double h = -static_cast<double>(p.y);
        if (std::isfinite(p.x) && std::isfinite(p.z) && h >= m_p.min_height && h <= m_p.max_height)
        {
            band.push_back(gridPoint(mrpt::math::TPoint3D(p)));
            extend(band.back());
        }
    }
    for (const auto& k : keyframes)
    {
        extend(gridPoint(k.T_world_frame.asTPose().translation()));
    }
    m_stats.band_points = band.size();
    if (!(x0 <= x1))
    {
        x0 = y0 = -1;
        x1 = y1 = 1;
    }
    const double margin = 2 * m_p.cell_size;
    const double cells = ((x1 - x0) / m_p.cell_size + 5) * ((y1 - y0) / m_p.cell_size + 5);
    if (!(cells <= MAX_CELLS))
    {
        throw std::invalid_argument(
            "OccupancyGridBuilder: the map spans " + std::to_string(x1 - x0) + " x " +
            std::to_string(y1 - y0) + " m: more than 1e8 cells of [OccupancyGrid] cell_size");
    }
    mrpt::maps::COccupancyGridMap2D grid;
    grid.setSize(
        static_cast<float>(x0 - margin), static_cast<float>(x1 + margin),
        static_cast<float>(y0 - margin), static_cast<float>(y1 + margin),
        static_cast<float>(m_p.cell_size), 0.5f);
    const int nx = static_cast<int>(grid.getSizeX()), ny = static_cast<int>(grid.getSizeY());
    const auto index = [&](double x, double y) -> long
    {
        const int cx = grid.x2idx(x), cy = grid.y2idx(y);
        return cx < 0 || cy < 0 || cx >= nx || cy >= ny ? -1 : cx + static_cast<long>(cy) * nx;
    };

    std::vector<int> hits(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0);
    for (const auto& q : band)
    {
        if (const long i = index(q.x, q.y); i >= 0)
        {
            ++hits[static_cast<std::size_t>(i)];
        }
    }
    const auto occupied = [&](long i)
    { return hits[static_cast<std::size_t>(i)] >= m_p.min_points; };

    // Free space: rays over each keyframe's field of view, half a cell per
    // step, until the first cell dense with points: the surface the ray
    // met. Dense cells no ray reaches lie behind the surfaces seen (stereo
    // depth noise spreads a wall's points along the viewing rays): unknown.
    enum : char
    {
        UNSEEN = 0,
        SEEN_THROUGH = 1,
        MET = 2
    };
    std::vector<char> seen(hits.size(), UNSEEN);
    const double fov = mrpt::DEG2RAD(m_p.fov_deg);
    const int rays = 1 + static_cast<int>(std::ceil(fov * m_p.max_range / m_p.cell_size));
    const int steps = static_cast<int>(std::ceil(m_p.max_range / (0.5 * m_p.cell_size)));
    for (const auto& k : keyframes)
    {
        const mrpt::math::TPoint2D o = gridPoint(k.T_world_frame.asTPose().translation());
        // The optical axis (camera +z) in the world, then in the grid.
        const auto R = k.T_world_frame.getRotationMatrix();
        const mrpt::math::TPoint2D axis = gridPoint({R(0, 2), R(1, 2), R(2, 2)});
        if (std::hypot(axis.x, axis.y) < 0.1)
        {
            continue;  // looking up or down: no horizontal view
        }
        const double heading = std::atan2(axis.y, axis.x);
        for (int r = 0; r < rays; ++r)
        {
            const double a = heading - 0.5 * fov + fov * (rays > 1 ? r / double(rays - 1) : 0.5);
            const double dx = std::cos(a), dy = std::sin(a);
            ++m_stats.rays;
            for (int s = 0; s <= steps; ++s)
            {
                const double d = 0.5 * m_p.cell_size * s;
                const long i = index(o.x + d * dx, o.y + d * dy);
                if (i < 0)
                {
                    break;
                }
                if (occupied(i))
                {
                    seen[static_cast<std::size_t>(i)] = MET;
                    break;
                }
                seen[static_cast<std::size_t>(i)] = SEEN_THROUGH;
            }
        }
    }
    for (int cy = 0; cy < ny; ++cy)
    {
        for (int cx = 0; cx < nx; ++cx)
        {
            const char s = seen[static_cast<std::size_t>(cx + static_cast<long>(cy) * nx)];
            if (s == MET)
            {
                grid.setCell(cx, cy, OCCUPIED);
                ++m_stats.occupied;
            }
            else if (s == SEEN_THROUGH)
            {
                grid.setCell(cx, cy, FREE);
                ++m_stats.free;
            }
        }
    }
    m_stats.cells = hits.size();
    return grid;
}

}  // namespace emslam::slam
