// SPDX-License-Identifier: BSD-3-Clause
// Trajectory compression, §2.2.4 (Eq. 13-14).
#include <emslam/rectify/Trajectory.h>

#include <utility>

namespace emslam::rectify
{
namespace
{
/** Eq. 13 on one map: observation 2k+1 brought into 2k's frame by a_{2k+1},
 * the union re-simplified at the map's cell size (§2.2.2) by the insertion. */
emslam::CEntropyVoxelMap fuseObservationPairs(
    const emslam::CEntropyVoxelMap& map, const std::vector<mrpt::poses::CPose3D>& actions)
{
    emslam::CEntropyVoxelMap fused(map.creationOptions(), map.insertionOptions);
    const std::size_t n = actions.size();
    for (std::size_t i = 0; i < n; i += 2)
    {
        emslam::maps::WeightedPointCloud cloud = map.observationCloud(i);
        if (i + 1 < n)
        {
            const mrpt::poses::CPose3D& a = actions[i + 1];
            const auto& second = map.observationCloud(i + 1);
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
        }
        fused.insertWeightedCloud(cloud, map.observationPose(i));
    }
    return fused;
}

/** Eq. 14: a'_0 = a_0, a'_k = a_{2k-1} ⊕ a_{2k}. */
std::vector<mrpt::poses::CPose3D> composeActionPairs(const std::vector<mrpt::poses::CPose3D>& a)
{
    std::vector<mrpt::poses::CPose3D> out;
    out.reserve((a.size() + 1) / 2);
    for (std::size_t i = 0; i < a.size(); i += 2)
    {
        out.push_back(i == 0 ? a[0] : a[i - 1] + a[i]);
    }
    return out;
}

/** Eq. 14 for the covariances of the egomotion's actions `a`. */
std::vector<ActionCovariance> composeCovariancePairs(
    const std::vector<mrpt::poses::CPose3D>& a, const std::vector<ActionCovariance>& c)
{
    std::vector<ActionCovariance> out;
    out.reserve((a.size() + 1) / 2);
    for (std::size_t i = 0; i < a.size(); i += 2)
    {
        out.push_back(i == 0 ? c[0] : composeCovariance(a[i - 1], c[i - 1], a[i], c[i]));
    }
    return out;
}
}  // namespace

bool Trajectory::needsCompression(int n_max) const
{
    return n_max > 0 && size() > static_cast<std::size_t>(n_max);
}

void Trajectory::compress()
{
    const std::size_t n = m_actions.size();
    if (n < 2)
    {
        return;
    }
    setResolutionLevel(0);  // fused clouds are simplified at l_d
    std::vector<std::vector<ElementFrame>> frames;
    frames.reserve((n + 1) / 2);
    for (std::size_t i = 0; i < n; i += 2)
    {
        std::vector<ElementFrame> members = m_frames[i];
        if (i + 1 < n)
        {
            for (ElementFrame f : m_frames[i + 1])
            {
                f.T_element_frame = m_actions[i + 1] + f.T_element_frame;
                members.push_back(f);
            }
        }
        frames.push_back(std::move(members));
    }
    const int threads = m_map.threads();
    m_map = fuseObservationPairs(m_map, m_actions);
    m_map.setThreads(threads);
    rebuildPhaseMaps();
    m_actions = composeActionPairs(m_actions);
    m_reference_cov = composeCovariancePairs(m_reference, m_reference_cov);
    m_reference_info.clear();
    for (const ActionCovariance& c : m_reference_cov)
    {
        m_reference_info.push_back(informationOf(c, dof()));
    }
    m_reference = composeActionPairs(m_reference);
    m_frames = std::move(frames);
    recomputePrior();
    m_undo_valid = false;
    ++m_compressions;
}

}  // namespace emslam::rectify
