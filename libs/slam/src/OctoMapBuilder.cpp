// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/OctoMapBuilder.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace emslam::slam
{
namespace
{
/** Every key of the section, once for load and save. */
void visit(OctoMapBuilder::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("resolution", p.resolution, "[m] map.bt voxel edge (0: no map.bt)");
    v.field("max_range", p.max_range, "[m] longest ray that occupies its end voxel");
}
}  // namespace

void OctoMapBuilder::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void OctoMapBuilder::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void OctoMapBuilder::TParameters::validate() const
{
    const auto bad = [](const std::string& key, const std::string& why)
    { throw std::invalid_argument("[OctoMapBuilder] " + key + ": " + why); };
    if (!(resolution >= 0) || !std::isfinite(resolution) || (resolution > 0 && resolution < 0.01))
    {
        bad("resolution", "must be 0 (no map.bt) or a length >= 0.01 m");
    }
    if (!(max_range > 0) || !std::isfinite(max_range))
    {
        bad("max_range", "must be a positive length");
    }
}

OctoMapBuilder::OctoMapBuilder(const TParameters& p) : m_p(p)
{
    m_p.validate();
}

std::unique_ptr<octomap::OcTree> OctoMapBuilder::build(
    const std::vector<KeyframeScan>& scans,
    const std::vector<emslam::rectify::TimedPose>& keyframes)
{
    if (m_p.resolution <= 0)
    {
        throw std::invalid_argument("OctoMapBuilder: [OctoMapBuilder] resolution is 0 (no map)");
    }
    m_stats = {};
    std::unordered_map<std::size_t, const mrpt::poses::CPose3D*> pose_of;
    for (const auto& k : keyframes)
    {
        pose_of[k.frame_index] = &k.T_world_frame;
    }
    auto tree = std::make_unique<octomap::OcTree>(m_p.resolution);
    octomap::Pointcloud world;
    for (const auto& scan : scans)
    {
        const auto it = pose_of.find(scan.frame_index);
        if (it == pose_of.end() || scan.cloud.size() == 0)
        {
            continue;
        }
        const mrpt::poses::CPose3D& T_world_cam = *it->second;
        world.clear();
        world.reserve(scan.cloud.size());
        for (const auto& p : scan.cloud.points)
        {
            double x = 0, y = 0, z = 0;
            T_world_cam.composePoint(p.x, p.y, p.z, x, y, z);
            world.push_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
        }
        // One update per voxel of the scan (discretized): a voxel both hit
        // and crossed by rays of the same scan counts as hit.
        tree->insertPointCloud(
            world,
            octomap::point3d(
                static_cast<float>(T_world_cam.x()), static_cast<float>(T_world_cam.y()),
                static_cast<float>(T_world_cam.z())),
            m_p.max_range, false, true);
        ++m_stats.scans;
        m_stats.points += scan.cloud.size();
    }
    tree->updateInnerOccupancy();
    return tree;
}

}  // namespace emslam::slam
