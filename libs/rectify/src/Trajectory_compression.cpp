// SPDX-License-Identifier: BSD-3-Clause
// Trajectory compression, §2.2.4 (Eq. 13-14).
#include <emslam/rectify/Trajectory.h>

#include <utility>

namespace emslam::rectify
{
void Trajectory::compress()
{
    const std::size_t n = m_actions.size();
    if (n < 2)
    {
        return;
    }
    emslam::CEntropyVoxelMap fused_map(m_map.creationOptions(), m_map.insertionOptions);
    std::vector<mrpt::poses::CPose3D> actions;
    std::vector<std::vector<ElementFrame>> frames;
    actions.reserve((n + 1) / 2);
    frames.reserve((n + 1) / 2);

    for (std::size_t i = 0; i < n; i += 2)
    {
        // Eq. 14: a'_0 = a_0, a'_k = a_{2k-1} ⊕ a_{2k}.
        actions.push_back(i == 0 ? m_actions[0] : m_actions[i - 1] + m_actions[i]);
        std::vector<ElementFrame> members = m_frames[i];
        emslam::maps::WeightedPointCloud cloud = m_map.observationCloud(i);
        if (i + 1 < n)
        {
            // Eq. 13: O' = O_2i ∪ (R_{2i+1} O_{2i+1} + t_{2i+1}).
            const mrpt::poses::CPose3D& a = m_actions[i + 1];
            const auto& second = m_map.observationCloud(i + 1);
            cloud.points.reserve(cloud.size() + second.size());
            cloud.weights.reserve(cloud.size() + second.size());
            for (std::size_t k = 0; k < second.size(); ++k)
            {
                const auto& p = second.points[k];
                double gx = 0, gy = 0, gz = 0;
                a.composePoint(p.x, p.y, p.z, gx, gy, gz);
                cloud.push_back(
                    {static_cast<float>(gx), static_cast<float>(gy), static_cast<float>(gz)},
                    second.weights[k]);
            }
            for (ElementFrame f : m_frames[i + 1])
            {
                f.T_element_frame = a + f.T_element_frame;
                members.push_back(f);
            }
        }
        // Re-simplified at l_d by the insertion (§2.2.2).
        fused_map.insertWeightedCloud(cloud, m_map.observationPose(i));
        frames.push_back(std::move(members));
    }
    m_map = std::move(fused_map);
    m_actions = std::move(actions);
    m_frames = std::move(frames);
    m_undo_valid = false;
    ++m_compressions;
}

}  // namespace emslam::rectify
