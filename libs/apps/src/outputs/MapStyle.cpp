// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/MapStyle.h>
#include <emslam/eval/TrajectoryMetrics.h>

#include <mrpt/img/color_maps.h>
#include <mrpt/math/CMatrixFixed.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace emslam::apps
{
mrpt::poses::CPose3D viewerFromCamera()
{
    mrpt::math::CMatrixDouble33 R;
    R.setZero();
    R(0, 2) = 1;   // forward → X
    R(1, 0) = -1;  // right → −Y
    R(2, 1) = -1;  // down → −Z
    mrpt::poses::CPose3D T;
    T.setRotationMatrix(R);
    return T;
}

mrpt::img::TColorf heightColor(double h, double lo, double hi)
{
    const double span = hi > lo ? hi - lo : 1.0;
    const double f = std::clamp((h - lo) / span, 0.0, 1.0);
    float r = 0, g = 0, b = 0;
    mrpt::img::jet2rgb(static_cast<float>(f), r, g, b);
    return {r, g, b};
}

emslam::io::TumTrajectory groundTruthInMapFrame(
    const emslam::io::TumTrajectory& ground_truth, const emslam::io::TumTrajectory& estimate)
{
    emslam::io::TumTrajectory out;
    if (ground_truth.empty() || estimate.empty())
    {
        return out;
    }
    const eval::AssociatedPoses pairs = eval::associateByTimestamp(ground_truth, estimate, 0.05);
    mrpt::poses::CPose3D T_map_gt;
    if (pairs.size() >= 3)
    {
        // alignPositions(a, b) lays b on a: here the ground truth on the estimate.
        T_map_gt = eval::alignPositions(pairs.est, pairs.gt, eval::Alignment::SE3).T_gt_est;
    }
    else
    {
        const double t0 = estimate.poses.front().t;
        const auto nearest = std::min_element(
            ground_truth.poses.begin(), ground_truth.poses.end(),
            [t0](const auto& a, const auto& b) { return std::abs(a.t - t0) < std::abs(b.t - t0); });
        T_map_gt = -nearest->pose;
    }
    for (const auto& p : ground_truth.poses)
    {
        out.add(p.t, T_map_gt + p.pose);
    }
    return out;
}

}  // namespace emslam::apps
