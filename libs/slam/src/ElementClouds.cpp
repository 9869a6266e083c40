// SPDX-License-Identifier: BSD-3-Clause
#include "PoseIndex.h"

#include <emslam/slam/ElementClouds.h>

#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace emslam::slam
{
namespace
{
const mrpt::poses::CPose3D& poseOf(const PoseIndex& index, std::size_t frame)
{
    const auto it = index.find(frame);
    if (it == index.end())
    {
        throw std::logic_error(
            "ElementClouds: frame " + std::to_string(frame) + " has no pose in the trajectory");
    }
    return *it->second;
}
}  // namespace

ElementClouds::ElementClouds(std::size_t n_max, double cell_size)
    : m_n_max(n_max), m_cell_size(cell_size)
{
}

void ElementClouds::append(std::size_t frame_index, IntensityCloud cloud)
{
    Element e;
    e.first_frame = frame_index;
    e.fused_at = frame_index;
    e.clouds.push_back({frame_index, std::move(cloud)});
    m_elements.push_back(std::move(e));
    if (m_n_max > 0 && m_elements.size() > m_n_max)
    {
        compress(frame_index);
    }
}

void ElementClouds::compress(std::size_t trigger_frame)
{
    // The pairing of Trajectory::compress(): 2i and 2i+1, an odd last one alone.
    std::vector<Element> out;
    out.reserve((m_elements.size() + 1) / 2);
    for (std::size_t i = 0; i < m_elements.size(); i += 2)
    {
        Element e = std::move(m_elements[i]);
        if (i + 1 < m_elements.size())
        {
            Element& second = m_elements[i + 1];
            e.frame_count += second.frame_count;
            e.fused_at = trigger_frame;
            for (auto& c : second.clouds)
            {
                e.clouds.push_back(std::move(c));
            }
        }
        out.push_back(std::move(e));
    }
    m_elements = std::move(out);
}

bool ElementClouds::hasPendingFusions() const
{
    for (const auto& e : m_elements)
    {
        if (e.clouds.size() > 1)
        {
            return true;
        }
    }
    return false;
}

void ElementClouds::fuse(const std::vector<emslam::rectify::TimedPose>& poses)
{
    if (!hasPendingFusions())
    {
        return;
    }
    const PoseIndex index = indexPoses(poses);
    for (auto& e : m_elements)
    {
        // Before the trajectory has fused the element too, the rectifier may
        // still move its frames apart.
        if (e.clouds.size() < 2 || index.count(e.fused_at) == 0)
        {
            continue;
        }
        const mrpt::poses::CPose3D& T_world_element = poseOf(index, e.first_frame);
        IntensityCloud all = std::move(e.clouds.front().cloud);
        for (std::size_t k = 1; k < e.clouds.size(); ++k)
        {
            const mrpt::poses::CPose3D T_element_frame =
                poseOf(index, e.clouds[k].frame_index) - T_world_element;
            all.appendTransformed(e.clouds[k].cloud, T_element_frame);
        }
        e.clouds.clear();
        e.clouds.push_back({e.first_frame, voxelDownsample(all, m_cell_size)});
    }
}

IntensityCloud ElementClouds::worldCloud(const std::vector<emslam::rectify::TimedPose>& poses) const
{
    const PoseIndex index = indexPoses(poses);
    IntensityCloud world;
    for (const auto& e : m_elements)
    {
        for (const auto& c : e.clouds)
        {
            world.appendTransformed(c.cloud, poseOf(index, c.frame_index));
        }
    }
    // Overlapping elements see the same surfaces: one point per cell in the end too.
    return voxelDownsample(world, m_cell_size);
}

std::vector<ElementClouds::Scan> ElementClouds::takeScans()
{
    std::vector<Scan> scans;
    for (auto& e : m_elements)
    {
        for (auto& c : e.clouds)
        {
            scans.push_back({c.frame_index, std::move(c.cloud)});
        }
        e.clouds.clear();
    }
    return scans;
}

void ElementClouds::requireSameElementsAs(const emslam::rectify::Trajectory& t) const
{
    const auto mismatch = [&](const std::string& what)
    {
        throw std::logic_error(
            "ElementClouds: the map cloud's elements differ from the trajectory's (" + what + ")");
    };
    if (t.size() != m_elements.size())
    {
        mismatch(
            std::to_string(m_elements.size()) + " elements, the trajectory has " +
            std::to_string(t.size()));
    }
    for (std::size_t i = 0; i < m_elements.size(); ++i)
    {
        const auto& frames = t.framesOf(i);
        if (frames.size() != m_elements[i].frame_count ||
            frames.front().frame_index != m_elements[i].first_frame)
        {
            mismatch("element " + std::to_string(i));
        }
    }
}

std::size_t ElementClouds::cloudCount() const
{
    std::size_t n = 0;
    for (const auto& e : m_elements)
    {
        n += e.clouds.size();
    }
    return n;
}

std::size_t ElementClouds::pointCount() const
{
    std::size_t n = 0;
    for (const auto& e : m_elements)
    {
        for (const auto& c : e.clouds)
        {
            n += c.cloud.size();
        }
    }
    return n;
}

std::size_t ElementClouds::memoryBytes() const
{
    std::size_t n = 0;
    for (const auto& e : m_elements)
    {
        for (const auto& c : e.clouds)
        {
            n += c.cloud.memoryBytes();
        }
    }
    return n;
}

}  // namespace emslam::slam
