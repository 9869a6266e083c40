// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/eval/SegmentErrors.h>

#include <mrpt/math/CQuaternion.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace emslam::eval
{
namespace
{
/** Angle of a rotation error [rad] from its unit quaternion, 2·atan2(|v|, |w|):
 * accurate down to zero, where the devkit's acos of the trace loses half
 * the digits. */
double rotationError(const mrpt::poses::CPose3D& err)
{
    mrpt::math::CQuaternionDouble q;
    err.getAsQuaternion(q);
    const double v = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
    return 2.0 * std::atan2(v, std::abs(q.r()));
}

/** Segments per path: the step is at most 1/20 of the path, 8 steps = 40 %. */
constexpr double STEPS_PER_PATH = 20.0;
constexpr int LENGTH_COUNT = 8;
/** The KITTI devkit's step; reached by paths of 2 km. */
constexpr double MAX_STEP_M = 100.0;
}  // namespace

std::vector<double> segmentLengthsFor(double path_length_m)
{
    const double raw = std::min(path_length_m / STEPS_PER_PATH, MAX_STEP_M);
    if (!(raw > 0) || !std::isfinite(raw))
    {
        return {};
    }
    // Largest 1, 2 or 5 x 10^k not above `raw`: round axis labels.
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double norm = raw / mag;
    const double step = (norm >= 5.0 ? 5.0 : norm >= 2.0 ? 2.0 : 1.0) * mag;
    std::vector<double> lengths;
    for (int k = 1; k <= LENGTH_COUNT; ++k)
    {
        lengths.push_back(k * step);
    }
    return lengths;
}

std::vector<SegmentError> segmentErrors(
    const std::vector<mrpt::poses::CPose3D>& gt,
    const std::vector<mrpt::poses::CPose3D>& est,
    const std::vector<double>& lengths_m,
    std::size_t step)
{
    if (gt.size() != est.size())
    {
        throw std::invalid_argument("segmentErrors: trajectories of different lengths");
    }
    step = std::max<std::size_t>(step, 1);
    // Distance along the ground-truth path at every pose (devkit's trajectoryDistances).
    std::vector<double> dist(gt.size(), 0.0);
    for (std::size_t i = 1; i < gt.size(); ++i)
    {
        dist[i] = dist[i - 1] + gt[i].distanceTo(gt[i - 1]);
    }
    std::vector<SegmentError> out;
    for (const double len : lengths_m)
    {
        SegmentError s;
        s.length_m = len;
        double sum_t = 0, sum_r = 0;
        for (std::size_t first = 0; first < gt.size(); first += step)
        {
            // The first pose strictly beyond `len` along the path, as the devkit.
            const auto it = std::upper_bound(
                dist.begin() + static_cast<std::ptrdiff_t>(first), dist.end(), dist[first] + len);
            if (it == dist.end())
            {
                continue;
            }
            const auto last = static_cast<std::size_t>(it - dist.begin());
            const mrpt::poses::CPose3D d_gt = gt[last] - gt[first];
            const mrpt::poses::CPose3D d_est = est[last] - est[first];
            const mrpt::poses::CPose3D err = d_gt - d_est;  // inv(d_est) * d_gt
            sum_t += err.norm() / len;
            sum_r += rotationError(err) / len;
            ++s.segments;
        }
        const double n = static_cast<double>(s.segments);
        s.t_err_percent =
            s.segments == 0 ? std::numeric_limits<double>::quiet_NaN() : 100.0 * sum_t / n;
        s.r_err_deg_per_m =
            s.segments == 0 ? std::numeric_limits<double>::quiet_NaN() : (180.0 / M_PI) * sum_r / n;
        out.push_back(s);
    }
    return out;
}

}  // namespace emslam::eval
