// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/MapDrawingContent.h>
#include <emslam/apps/MapperLiveFeed.h>

#include <mrpt/core/format.h>

#include <map>

namespace emslam::apps
{
namespace
{
LiveViewer::Options optionsFor(const std::string& title)
{
    LiveViewer::Options o;
    o.title = title;
    return o;
}

mrpt::math::TPoint3Df positionOf(const mrpt::poses::CPose3D& p)
{
    return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
}
}  // namespace

MapperLiveFeed::MapperLiveFeed(const std::string& title) : m_viewer(optionsFor(title)) {}

void MapperLiveFeed::update(const slam::EntropySlam& m)
{
    if (!m_viewer.active() || m.egomotionPoses().empty())
    {
        return;
    }
    const mrpt::poses::CPose3D& T_world_cam = m.egomotionPoses().back().T_world_frame;
    for (const auto& added : m.addedClouds())
    {
        const auto& o = m.parameters().mapper;
        if (!m_fusion)
        {
            m_fusion.emplace(o.fused_voxel_size, o.max_point_sigma, o.max_observation_sigma);
        }
        const slam::IntensityCloud certain =
            m_fusion->add(added.cloud, m.egomotionPoses().at(added.frame_index).T_world_frame);
        // The same ceiling cut as map.3Dscene, so the trajectories stay visible.
        m_viewer.addMapPoints(cutAboveHeight(certain, o.export_max_height));
    }
    if (!m_viewer.wantsSnapshot())
    {
        return;
    }
    LiveViewSnapshot s;
    s.egomotion.reserve(m.egomotionPoses().size());
    for (const auto& p : m.egomotionPoses())
    {
        s.egomotion.push_back(positionOf(p.T_world_frame));
    }
    std::map<std::size_t, mrpt::math::TPoint3Df> keyframe_at;
    for (const auto& p : m.currentSlamPoses())
    {
        s.slam.push_back(positionOf(p.T_world_frame));
        keyframe_at[p.frame_index] = s.slam.back();
    }
    for (const auto& [from, to] : m.currentLoops())
    {
        const auto a = keyframe_at.find(from), b = keyframe_at.find(to);
        if (a != keyframe_at.end() && b != keyframe_at.end())
        {
            s.loops.emplace_back(a->second, b->second);
        }
    }
    s.camera = T_world_cam;
    if (!m.lastImage().empty())
    {
        s.image = mrpt::img::CImage(m.lastImage(), mrpt::img::DEEP_COPY);
    }
    s.status = mrpt::format(
        "frame %zu, accepted %zu, egomotion failures %zu, energy %.4f", m.frameCount(),
        m.acceptedCount(), m.egomotionFailures(), m.currentEnergy());
    m_viewer.push(std::move(s));
}

}  // namespace emslam::apps
