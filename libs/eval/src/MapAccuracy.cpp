// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/eval/MapAccuracy.h>
#include <emslam/eval/PointKdTree.h>
#include <emslam/io/Json.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace emslam::eval
{
namespace
{
void requireMatchingSizes(const ReferenceSurface& r)
{
    if (!r.normals.empty() && r.normals.size() != r.points.size())
    {
        throw std::invalid_argument("MapAccuracy: the reference has normals for some points only");
    }
    if (!r.seen_range.empty() && r.seen_range.size() != r.points.size())
    {
        throw std::invalid_argument(
            "MapAccuracy: the reference has seen ranges for some points only");
    }
}

/** Distance of `p` to the surface around sample `i` (see the class comment). */
double surfaceDistance(const mrpt::math::TPoint3Df& p, const ReferenceSurface& r, std::size_t i)
{
    const auto& q = r.points[i];
    const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (r.normals.empty())
    {
        return std::sqrt(d2);
    }
    const auto& n = r.normals[i];
    const double along = dx * n.x + dy * n.y + dz * n.z;
    const double sideways = std::sqrt(std::max(0.0, d2 - along * along));
    const double overshoot = std::max(0.0, sideways - r.spacing / std::sqrt(2.0));
    return std::sqrt(along * along + overshoot * overshoot);
}
}  // namespace

double MapAccuracy::percentile(std::vector<double> values, double p)
{
    if (values.empty())
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    const auto n = static_cast<double>(values.size());
    const auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(p / 100.0 * n - 1e-9)));
    const std::size_t k = std::min(rank, values.size()) - 1;
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
    return values[k];
}

MapAccuracy MapAccuracy::compute(
    const std::vector<mrpt::math::TPoint3Df>& map,
    const ReferenceSurface& reference,
    const Options& options)
{
    if (map.empty())
    {
        throw std::invalid_argument("MapAccuracy: the map has no points");
    }
    if (reference.points.empty())
    {
        throw std::invalid_argument("MapAccuracy: the reference surface has no points");
    }
    requireMatchingSizes(reference);
    MapAccuracy a;
    a.options = options;
    a.map_points = map.size();
    a.reference_points = reference.points.size();

    const PointKdTree truth(reference.points);
    std::vector<double> dist(map.size());
    double sum = 0;
    for (std::size_t k = 0; k < map.size(); ++k)
    {
        float d2 = 0;
        dist[k] = surfaceDistance(map[k], reference, truth.nearest(map[k], d2));
        sum += dist[k];
    }
    a.mean_m = sum / static_cast<double>(map.size());
    a.median_m = percentile(dist, 50);
    a.p90_m = percentile(std::move(dist), 90);

    const PointKdTree mapped(map);
    const double reach2 = options.completeness_distance * options.completeness_distance;
    std::size_t covered = 0, near = 0, near_covered = 0;
    for (std::size_t i = 0; i < reference.points.size(); ++i)
    {
        float d2 = 0;
        mapped.nearest(reference.points[i], d2);
        const bool hit = d2 <= reach2;
        covered += hit ? 1 : 0;
        if (!reference.seen_range.empty() && reference.seen_range[i] <= options.near_range)
        {
            ++near;
            near_covered += hit ? 1 : 0;
        }
    }
    a.completeness = static_cast<double>(covered) / static_cast<double>(a.reference_points);
    a.near_reference_points = near;
    if (near > 0)
    {
        a.completeness_near = static_cast<double>(near_covered) / static_cast<double>(near);
    }
    return a;
}

std::string MapAccuracy::toJson() const
{
    std::ostringstream s;
    s << "{\n"
      << "  \"map_points\": " << map_points << ",\n"
      << "  \"reference_points\": " << reference_points << ",\n"
      << "  \"accuracy_median_m\": " << io::jsonNumber(median_m) << ",\n"
      << "  \"accuracy_p90_m\": " << io::jsonNumber(p90_m) << ",\n"
      << "  \"accuracy_mean_m\": " << io::jsonNumber(mean_m) << ",\n"
      << "  \"completeness_distance_m\": " << io::jsonNumber(options.completeness_distance) << ",\n"
      << "  \"completeness\": " << io::jsonNumber(completeness) << ",\n"
      << "  \"near_range_m\": " << io::jsonNumber(options.near_range) << ",\n"
      << "  \"near_reference_points\": " << near_reference_points << ",\n"
      << "  \"completeness_near\": " << io::jsonNumber(completeness_near) << "\n"
      << "}\n";
    return s.str();
}

}  // namespace emslam::eval
