// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/eval/OccupancyGridAccuracy.h>
#include <emslam/io/Json.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace emslam::eval
{
namespace
{
bool occupied(const mrpt::maps::COccupancyGridMap2D& g, int cx, int cy)
{
    return cx >= 0 && cy >= 0 && static_cast<unsigned>(cx) < g.getSizeX() &&
           static_cast<unsigned>(cy) < g.getSizeY() &&
           g.getCell(cx, cy) < 0.5F;  // MRPT cells hold P(free)
}

/** Occupied cells of `from`, and how many of them have an occupied cell of
 * `to` within `tol` cells. */
std::pair<std::size_t, std::size_t> matchedCells(
    const mrpt::maps::COccupancyGridMap2D& from, const mrpt::maps::COccupancyGridMap2D& to, int tol)
{
    std::size_t cells = 0, matched = 0;
    for (int cy = 0; cy < static_cast<int>(from.getSizeY()); ++cy)
    {
        for (int cx = 0; cx < static_cast<int>(from.getSizeX()); ++cx)
        {
            if (!occupied(from, cx, cy))
            {
                continue;
            }
            ++cells;
            const int tx = to.x2idx(from.idx2x(static_cast<std::size_t>(cx)));
            const int ty = to.y2idx(from.idx2y(static_cast<std::size_t>(cy)));
            bool hit = false;
            for (int dy = -tol; dy <= tol && !hit; ++dy)
            {
                for (int dx = -tol; dx <= tol && !hit; ++dx)
                {
                    hit = occupied(to, tx + dx, ty + dy);
                }
            }
            matched += hit ? 1 : 0;
        }
    }
    return {cells, matched};
}

double ratio(std::size_t a, std::size_t b)
{
    return b == 0 ? std::numeric_limits<double>::quiet_NaN()
                  : static_cast<double>(a) / static_cast<double>(b);
}
}  // namespace

OccupancyGridAccuracy OccupancyGridAccuracy::compute(
    const mrpt::maps::COccupancyGridMap2D& estimate,
    const mrpt::maps::COccupancyGridMap2D& truth,
    int tolerance)
{
    const double re = estimate.getResolution(), rt = truth.getResolution();
    if (!(std::abs(re - rt) <= 1e-3 * rt))
    {
        std::ostringstream s;
        s << "OccupancyGridAccuracy: the grids have different cell sizes (" << re << " m and " << rt
          << " m)";
        throw std::invalid_argument(s.str());
    }
    if (tolerance < 0)
    {
        throw std::invalid_argument("OccupancyGridAccuracy: the tolerance must be >= 0 cells");
    }
    OccupancyGridAccuracy a;
    a.tolerance_cells = tolerance;
    a.cell_size = rt;
    std::tie(a.estimated_occupied, a.estimated_matched) = matchedCells(estimate, truth, tolerance);
    std::tie(a.true_occupied, a.true_matched) = matchedCells(truth, estimate, tolerance);
    a.precision = ratio(a.estimated_matched, a.estimated_occupied);
    a.recall = ratio(a.true_matched, a.true_occupied);
    // Both defined and both 0: no match at all, F1 0 (not 0 / 0).
    a.f1 =
        a.precision + a.recall == 0 ? 0.0 : 2 * a.precision * a.recall / (a.precision + a.recall);
    return a;
}

std::string OccupancyGridAccuracy::toJson() const
{
    std::ostringstream s;
    s << "{\n"
      << "  \"cell_size_m\": " << io::jsonNumber(cell_size) << ",\n"
      << "  \"tolerance_cells\": " << tolerance_cells << ",\n"
      << "  \"estimated_occupied\": " << estimated_occupied << ",\n"
      << "  \"true_occupied\": " << true_occupied << ",\n"
      << "  \"precision\": " << io::jsonNumber(precision) << ",\n"
      << "  \"recall\": " << io::jsonNumber(recall) << ",\n"
      << "  \"f1\": " << io::jsonNumber(f1) << "\n"
      << "}\n";
    return s.str();
}

}  // namespace emslam::eval
