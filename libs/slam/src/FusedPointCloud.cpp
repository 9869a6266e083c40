// SPDX-License-Identifier: BSD-3-Clause
#include "VoxelKey.h"

#include <emslam/slam/FusedPointCloud.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

namespace emslam::slam
{
namespace
{
/** A point's weight 1/σ²; a σ of 0 counts as 1 mm. */
double weightOf(double sigma)
{
    const double s = std::max(sigma, 1e-3);
    return 1.0 / (s * s);
}

/** The search along a ray reaches ±this many σ. */
constexpr double RAY_SEARCH_SIGMAS = 2.0;
/** The width of the preference for nearer cells, in sigmas. */
constexpr double PREFERENCE_SIGMAS = 2.0;

struct VoxelSum
{
    double w{0}, x{0}, y{0}, z{0}, grey{0};
    std::size_t points{0};
};

constexpr std::uint64_t UNUSED = ~std::uint64_t{0};

/** Weight per voxel key, in one open-addressing table (linear probing,
 * power-of-two size, at most three quarters full): the ray search looks up tens of
 * voxels per point, and std::unordered_map's node per key made that most of
 * the fusion's time. Keys are voxelKey()s (63 bits), so UNUSED marks a free
 * slot. Not maps::WeightedHistogram: its entropy bookkeeping and load of at
 * most 1/2 raised the KITTI run's peak RSS from 216 to 230 MB (same map). */
class Evidence
{
public:
    explicit Evidence(std::size_t expected)
    {
        std::size_t capacity = 16;
        while (3 * capacity < 4 * expected)
        {
            capacity *= 2;
        }
        m_keys.assign(capacity, UNUSED);
        m_values.assign(capacity, 0.0);
        m_mask = capacity - 1;
    }

    void add(std::uint64_t key, double w)
    {
        if (4 * (m_used + 1) > 3 * m_keys.size())
        {
            grow();
        }
        std::size_t i = slot(key);
        while (m_keys[i] != key && m_keys[i] != UNUSED)
        {
            i = (i + 1) & m_mask;
        }
        if (m_keys[i] == UNUSED)
        {
            m_keys[i] = key;
            ++m_used;
        }
        m_values[i] += w;
    }

    /** The weight of `key`, or nullptr if no point is in it. */
    const double* find(std::uint64_t key) const
    {
        for (std::size_t i = slot(key);; i = (i + 1) & m_mask)
        {
            if (m_keys[i] == key)
            {
                return &m_values[i];
            }
            if (m_keys[i] == UNUSED)
            {
                return nullptr;
            }
        }
    }

private:
    std::size_t slot(std::uint64_t key) const
    {
        // Fibonacci hashing: neighbouring voxels land far apart.
        return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 32) & m_mask;
    }

    void grow()
    {
        Evidence bigger(m_keys.size());
        for (std::size_t i = 0; i < m_keys.size(); ++i)
        {
            if (m_keys[i] != UNUSED)
            {
                bigger.add(m_keys[i], m_values[i]);
            }
        }
        *this = std::move(bigger);
    }

    std::vector<std::uint64_t> m_keys;
    std::vector<double> m_values;
    std::size_t m_mask{0}, m_used{0};
};

/** The voxel, along the ray from `o` through `p` within ±RAY_SEARCH_SIGMAS σ,
 * with the most evidence, nearer ones preferred softly (a Gaussian of
 * PREFERENCE_SIGMAS σ) so ties stay near; `own` (p's voxel now) is scored
 * at t = 0, so ties stay put. */
std::uint64_t bestVoxelAlongRay(
    const mrpt::math::TPoint3Df& p,
    const mrpt::math::TPoint3D& o,
    double sigma,
    std::uint64_t own,
    const Evidence& evidence,
    double voxel_size)
{
    const double step = 0.5 * voxel_size;
    double dx = p.x - o.x, dy = p.y - o.y, dz = p.z - o.z;
    const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(r > 1e-6))
    {
        return own;
    }
    dx /= r;
    dy /= r;
    dz /= r;
    const double inv_voxel = 1.0 / voxel_size;
    const int steps = static_cast<int>(std::ceil(RAY_SEARCH_SIGMAS * sigma / step));
    const double inv_two_var = 0.5 / (PREFERENCE_SIGMAS * PREFERENCE_SIGMAS * sigma * sigma);
    std::uint64_t best = own;
    double best_score = -1.0;
    std::uint64_t last = UNUSED;
    for (int k = -steps; k <= steps; ++k)
    {
        const double t = k * step;
        if (t < -r)
        {
            continue;  // not behind the camera
        }
        const std::uint64_t key = voxelKey(p.x + t * dx, p.y + t * dy, p.z + t * dz, inv_voxel);
        if (key == last)
        {
            continue;
        }
        last = key;
        const double* weight = evidence.find(key);
        if (weight == nullptr || !(*weight > best_score))
        {
            continue;  // absent, or cannot win: the preference is at most 1
        }
        const double tt = key == own ? 0.0 : t;
        const double score = *weight * std::exp(-tt * tt * inv_two_var);
        if (score > best_score)
        {
            best_score = score;
            best = key;
        }
    }
    return best;
}

/** visit(i) for i < n, in contiguous ranges on up to as many threads as the
 * machine has cores (one below 20,000 items: not worth a thread). */
template <typename Visit>
void forEachInParallel(std::size_t n, const Visit& visit)
{
    const std::size_t threads =
        n < 20000 ? 1 : std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 8);
    const auto range = [&](std::size_t t)
    {
        for (std::size_t i = n * t / threads; i < n * (t + 1) / threads; ++i)
        {
            visit(i);
        }
    };
    std::vector<std::thread> workers;
    for (std::size_t t = 1; t < threads; ++t)
    {
        workers.emplace_back(range, t);
    }
    range(0);
    for (auto& w : workers)
    {
        w.join();
    }
}

/** Each point's voxel weighted by 1/σ²: the evidence of the assignment. */
Evidence evidenceOf(
    const std::vector<std::uint64_t>& voxel, const std::vector<float>& sigma, std::size_t used)
{
    Evidence evidence(used / 3 + 16);  // KITTI, the hall: 0.3 voxels per point
    for (std::size_t i = 0; i < voxel.size(); ++i)
    {
        if (voxel[i] != UNUSED)
        {
            evidence.add(voxel[i], weightOf(sigma[i]));
        }
    }
    return evidence;
}

/** The 1/σ²-weighted sums of the points per voxel of `voxel`; `sum_of[i]`:
 * the sum point i joined. Counts the points that moved to another voxel. */
std::vector<VoxelSum> sumPerVoxel(
    const std::vector<std::uint64_t>& voxel,
    const std::vector<mrpt::math::TPoint3Df>& points,
    const std::vector<float>& sigma,
    const std::vector<std::uint8_t>& grey,
    double inv_voxel,
    std::vector<std::size_t>& sum_of,
    std::size_t& moved_points)
{
    const std::size_t n = points.size();
    sum_of.assign(n, 0);
    std::unordered_map<std::uint64_t, std::size_t> index_of;
    std::vector<VoxelSum> sums;
    index_of.reserve(n / 2 + 16);
    for (std::size_t i = 0; i < n; ++i)
    {
        if (voxel[i] == UNUSED)
        {
            continue;
        }
        const auto& p = points[i];
        if (voxel[i] != voxelKey(p.x, p.y, p.z, inv_voxel))
        {
            ++moved_points;
        }
        const auto [it, inserted] = index_of.try_emplace(voxel[i], sums.size());
        if (inserted)
        {
            sums.emplace_back();
        }
        VoxelSum& s = sums[it->second];
        const double w = weightOf(sigma[i]);
        s.w += w;
        s.x += w * p.x;
        s.y += w * p.y;
        s.z += w * p.z;
        s.grey += w * grey[i];
        ++s.points;
        sum_of[i] = it->second;
    }
    return sums;
}
}  // namespace

FusedPointCloud::FusedPointCloud(const TOptions& o) : m_o(o)
{
    if (!(m_o.voxel_size >= 0.001) || !std::isfinite(m_o.voxel_size))
    {
        throw std::invalid_argument(
            "FusedPointCloud: voxel size " + std::to_string(m_o.voxel_size) +
            " m: must be at least 0.001 m");
    }
    if (!(m_o.max_sigma > 0) || !(m_o.max_observation_sigma > 0))
    {
        throw std::invalid_argument("FusedPointCloud: the sigma limits must be positive");
    }
    if (m_o.ray_passes < 0)
    {
        throw std::invalid_argument("FusedPointCloud: ray_passes must be >= 0");
    }
}

std::size_t FusedPointCloud::add(const IntensityCloud& cloud, const mrpt::math::TPoint3D& origin)
{
    const std::size_t first = m_points.size();
    const auto view = static_cast<std::uint32_t>(m_origins.size());
    m_origins.push_back(origin);
    const bool sigmas = cloud.hasSigma();
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
        m_points.push_back(cloud.points[i]);
        m_sigma.push_back(sigmas ? cloud.sigma[i] : static_cast<float>(m_o.voxel_size));
        m_grey.push_back(i < cloud.intensity.size() ? cloud.intensity[i] : 0);
        m_view.push_back(view);
    }
    return first;
}

std::size_t FusedPointCloud::addView(
    const IntensityCloud& cloud_in_camera, const mrpt::poses::CPose3D& T_world_cam)
{
    IntensityCloud world;
    world.appendTransformed(cloud_in_camera, T_world_cam);
    return add(world, {T_world_cam.x(), T_world_cam.y(), T_world_cam.z()});
}

void FusedPointCloud::fuse()
{
    const std::size_t n = m_points.size();
    const double inv_voxel = 1.0 / m_o.voxel_size;
    m_stats = {};
    m_stats.points = n;
    // The voxel each point is fused in: its own to begin with.
    std::vector<std::uint64_t> voxel(n, UNUSED);
    for (std::size_t i = 0; i < n; ++i)
    {
        const auto& p = m_points[i];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
            std::isfinite(m_sigma[i]) && m_sigma[i] <= m_o.max_observation_sigma)
        {
            voxel[i] = voxelKey(p.x, p.y, p.z, inv_voxel);
            ++m_stats.used_points;
        }
    }
    // Along the rays: each pass follows the previous pass's evidence (a mean
    // shift along each ray). A point within half a voxel of its depth has
    // nowhere else to go.
    const int passes = m_o.along_rays ? m_o.ray_passes : 0;
    for (int pass = 0; pass < passes; ++pass)
    {
        const Evidence evidence = evidenceOf(voxel, m_sigma, m_stats.used_points);
        std::vector<std::uint64_t> next = voxel;
        // Each point reads the evidence and writes its own voxel: the points
        // split between threads give the same result as one thread.
        forEachInParallel(
            n,
            [&](std::size_t i)
            {
                if (voxel[i] != UNUSED && m_sigma[i] > 0.5 * m_o.voxel_size)
                {
                    next[i] = bestVoxelAlongRay(
                        m_points[i], m_origins[m_view[i]], m_sigma[i], voxel[i], evidence,
                        m_o.voxel_size);
                }
            });
        voxel.swap(next);
    }
    std::vector<std::size_t> sum_of;
    const std::vector<VoxelSum> sums =
        sumPerVoxel(voxel, m_points, m_sigma, m_grey, inv_voxel, sum_of, m_stats.moved_points);
    m_stats.voxels = sums.size();

    // Gate the voxels by the uncertainty left.
    m_cloud = IntensityCloud();
    std::vector<std::int32_t> kept(sums.size(), -1);
    for (std::size_t v = 0; v < sums.size(); ++v)
    {
        const VoxelSum& s = sums[v];
        const double sigma = 1.0 / std::sqrt(s.w);
        if (!(sigma <= m_o.max_sigma))
        {
            continue;
        }
        kept[v] = static_cast<std::int32_t>(m_cloud.size());
        m_cloud.points.emplace_back(
            static_cast<float>(s.x / s.w), static_cast<float>(s.y / s.w),
            static_cast<float>(s.z / s.w));
        m_cloud.intensity.push_back(
            static_cast<std::uint8_t>(std::clamp(std::lround(s.grey / s.w), 0L, 255L)));
        m_cloud.sigma.push_back(static_cast<float>(sigma));
        m_stats.kept_points += s.points;
    }
    m_stats.kept_voxels = m_cloud.size();
    m_fused_index.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i)
    {
        if (voxel[i] != UNUSED)
        {
            m_fused_index[i] = kept[sum_of[i]];
        }
    }
}

}  // namespace emslam::slam
