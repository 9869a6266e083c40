// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/KeyframeClouds.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace emslam::slam
{
namespace
{
constexpr double COORDINATE_UNITS = 32767.0;  // int16: ±32767
constexpr double SIGMA_UNITS = 65535.0;       // uint16

bool finite(const mrpt::math::TPoint3Df& p)
{
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

std::size_t packedBytes(std::size_t points, bool sigmas)
{
    return points * (3 * sizeof(std::int16_t) + 1 + (sigmas ? sizeof(std::uint16_t) : 0));
}
}  // namespace

KeyframeClouds::KeyframeClouds(double max_sigma, std::size_t max_bytes)
    : m_max_sigma(max_sigma), m_max_bytes(max_bytes)
{
}

void KeyframeClouds::append(std::size_t frame_index, const IntensityCloud& cloud)
{
    const std::size_t ordinal = m_appended++;
    if (ordinal % m_stride != 0)
    {
        return;
    }
    const bool sigmas = cloud.hasSigma();
    std::vector<std::size_t> kept;
    kept.reserve(cloud.size());
    double extent = 0, largest_sigma = 0;
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
        const auto& p = cloud.points[i];
        if (!finite(p) || (sigmas && !(std::isfinite(cloud.sigma[i]) && cloud.sigma[i] >= 0 &&
                                       cloud.sigma[i] <= m_max_sigma)))
        {
            continue;
        }
        kept.push_back(i);
        extent =
            std::max({extent, std::abs(double(p.x)), std::abs(double(p.y)), std::abs(double(p.z))});
        if (sigmas)
        {
            largest_sigma = std::max(largest_sigma, double(cloud.sigma[i]));
        }
    }
    PackedScan s;
    s.frame_index = frame_index;
    s.ordinal = ordinal;
    s.scale = static_cast<float>(extent > 0 ? extent / COORDINATE_UNITS : 1.0);
    s.sigma_scale = static_cast<float>(sigmas ? std::max(largest_sigma, 1e-9) / SIGMA_UNITS : 0.0);
    s.xyz.reserve(3 * kept.size());
    s.grey.reserve(kept.size());
    s.sigma.reserve(sigmas ? kept.size() : 0);
    const auto unit = [&](float v) { return static_cast<std::int16_t>(std::lround(v / s.scale)); };
    for (const std::size_t i : kept)
    {
        const auto& p = cloud.points[i];
        s.xyz.push_back(unit(p.x));
        s.xyz.push_back(unit(p.y));
        s.xyz.push_back(unit(p.z));
        s.grey.push_back(i < cloud.intensity.size() ? cloud.intensity[i] : 0);
        if (sigmas)
        {
            s.sigma.push_back(
                static_cast<std::uint16_t>(std::lround(cloud.sigma[i] / s.sigma_scale)));
        }
    }
    m_bytes += packedBytes(kept.size(), sigmas);
    m_scans.push_back(std::move(s));
    thin();
}

void KeyframeClouds::thin()
{
    while (m_max_bytes > 0 && m_bytes > m_max_bytes && m_scans.size() > 1)
    {
        m_stride *= 2;
        std::vector<PackedScan> kept;
        kept.reserve(m_scans.size() / 2 + 1);
        m_bytes = 0;
        for (PackedScan& s : m_scans)
        {
            if (s.ordinal % m_stride == 0)
            {
                m_bytes += packedBytes(s.grey.size(), !s.sigma.empty());
                kept.push_back(std::move(s));
            }
        }
        m_scans = std::move(kept);
    }
}

std::vector<KeyframeScan> KeyframeClouds::takeScans()
{
    std::vector<KeyframeScan> scans;
    scans.reserve(m_scans.size());
    for (PackedScan& s : m_scans)
    {
        KeyframeScan out;
        out.frame_index = s.frame_index;
        const std::size_t n = s.grey.size();
        out.cloud.points.reserve(n);
        for (std::size_t i = 0; i < n; ++i)
        {
            out.cloud.points.emplace_back(
                s.xyz[3 * i] * s.scale, s.xyz[3 * i + 1] * s.scale, s.xyz[3 * i + 2] * s.scale);
        }
        out.cloud.intensity = std::move(s.grey);
        out.cloud.sigma.reserve(s.sigma.size());
        for (const std::uint16_t u : s.sigma)
        {
            out.cloud.sigma.push_back(u * s.sigma_scale);
        }
        scans.push_back(std::move(out));
        s = PackedScan();  // its memory goes as the unpacked copy grows
    }
    m_scans.clear();
    m_bytes = 0;
    return scans;
}

std::size_t KeyframeClouds::pointCount() const
{
    std::size_t n = 0;
    for (const auto& s : m_scans)
    {
        n += s.grey.size();
    }
    return n;
}

std::size_t KeyframeClouds::memoryBytes() const
{
    std::size_t bytes = m_scans.capacity() * sizeof(PackedScan);
    for (const auto& s : m_scans)
    {
        bytes += s.xyz.capacity() * sizeof(std::int16_t) +
                 s.sigma.capacity() * sizeof(std::uint16_t) + s.grey.capacity();
    }
    return bytes;
}

}  // namespace emslam::slam
