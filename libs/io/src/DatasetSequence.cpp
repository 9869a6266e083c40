// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DatasetSequence.h>

namespace emslam::io
{
double DatasetSequence::meanFrameRate(double fallback) const
{
    const std::size_t n = size();
    if (n < 2)
    {
        return fallback;
    }
    const double span = timestamp(n - 1) - timestamp(0);
    return span > 0 ? static_cast<double>(n - 1) / span : fallback;
}

TumTrajectory DatasetSequence::groundTruthTrajectory() const
{
    TumTrajectory gt;
    std::optional<mrpt::poses::CPose3D> T_world_ref;
    for (std::size_t i = 0; hasGroundTruth() && i < size(); ++i)
    {
        const auto T_world_cam = groundTruthAt(i);
        if (!T_world_cam)
        {
            continue;
        }
        if (!T_world_ref)
        {
            T_world_ref = *T_world_cam;
            gt.add(timestamp(i), mrpt::poses::CPose3D());
            continue;
        }
        gt.add(timestamp(i), *T_world_cam - *T_world_ref);  // inv(T_world_ref) * T_world_cam
    }
    return gt;
}

}  // namespace emslam::io
