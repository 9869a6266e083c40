// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/eval/SegmentErrors.h>
#include <emslam/eval/TrajectoryMetrics.h>
#include <emslam/io/Json.h>
#include <emslam/io/NumberText.h>

#include <mrpt/math/CMatrixFixed.h>

#include <Eigen/Dense>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace emslam::eval
{
namespace
{
constexpr double UNDEFINED = std::numeric_limits<double>::quiet_NaN();
/** The KITTI devkit's segment lengths [m], used on paths of at least the first one. */
constexpr double KITTI_LENGTHS[] = {100, 200, 300, 400, 500, 600, 700, 800};
/** Fractions of the path used as segment lengths on shorter paths. */
constexpr double SHORT_FRACTIONS[] = {0.1, 0.2, 0.3, 0.4, 0.5};

/** Indices of `traj` sorted by time (stable: equal stamps keep file order). */
std::vector<std::size_t> timeOrder(const emslam::io::TumTrajectory& traj)
{
    std::vector<std::size_t> idx(traj.size());
    std::iota(idx.begin(), idx.end(), std::size_t{0});
    std::stable_sort(
        idx.begin(), idx.end(),
        [&](std::size_t a, std::size_t b) { return traj.poses[a].t < traj.poses[b].t; });
    return idx;
}

}  // namespace

Alignment parseAlignment(const std::string& s)
{
    std::string l = s;
    std::transform(
        l.begin(), l.end(), l.begin(),
        [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (l == "none")
    {
        return Alignment::None;
    }
    if (l == "se3")
    {
        return Alignment::SE3;
    }
    if (l == "sim3")
    {
        return Alignment::Sim3;
    }
    throw std::invalid_argument("unknown alignment '" + s + "' (expected se3, sim3 or none)");
}

std::string alignmentName(Alignment a)
{
    switch (a)
    {
        case Alignment::None:
            return "none";
        case Alignment::SE3:
            return "se3";
        case Alignment::Sim3:
            return "sim3";
    }
    return "?";
}

mrpt::poses::CPose3D SimilarityTransform::apply(const mrpt::poses::CPose3D& T_ref_body) const
{
    // Scale the position in the estimate's frame, then move it rigidly.
    mrpt::poses::CPose3D scaled = T_ref_body;
    scaled.x(scale * T_ref_body.x());
    scaled.y(scale * T_ref_body.y());
    scaled.z(scale * T_ref_body.z());
    return T_gt_est + scaled;
}

void SimilarityTransform::applyToPoints(std::vector<mrpt::math::TPoint3Df>& points) const
{
    for (auto& p : points)
    {
        double x = 0, y = 0, z = 0;
        T_gt_est.composePoint(scale * p.x, scale * p.y, scale * p.z, x, y, z);
        p = {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)};
    }
}

SimilarityTransform alignPositions(
    const std::vector<mrpt::poses::CPose3D>& gt,
    const std::vector<mrpt::poses::CPose3D>& est,
    Alignment mode)
{
    if (gt.size() != est.size() || gt.empty())
    {
        throw std::invalid_argument(
            "alignPositions: need two equally long, non-empty position lists (got " +
            std::to_string(gt.size()) + " and " + std::to_string(est.size()) + ")");
    }
    SimilarityTransform out;
    if (mode == Alignment::None)
    {
        return out;
    }
    const auto n = static_cast<Eigen::Index>(gt.size());
    Eigen::Matrix3Xd X(3, n), Y(3, n);
    for (Eigen::Index i = 0; i < n; ++i)
    {
        const auto& e = est[static_cast<std::size_t>(i)];
        const auto& g = gt[static_cast<std::size_t>(i)];
        X.col(i) << e.x(), e.y(), e.z();
        Y.col(i) << g.x(), g.y(), g.z();
    }
    const Eigen::Vector3d mx = X.rowwise().mean(), my = Y.rowwise().mean();
    const Eigen::Matrix3Xd Xc = X.colwise() - mx, Yc = Y.colwise() - my;
    const Eigen::Matrix3d sigma = Yc * Xc.transpose() / static_cast<double>(n);
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Vector3d d(1, 1, 1);
    // A reflection would fit better on degenerate sets; force a rotation.
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0)
    {
        d(2) = -1;
    }
    const Eigen::Matrix3d R = svd.matrixU() * d.asDiagonal() * svd.matrixV().transpose();
    const double var_x = Xc.squaredNorm() / static_cast<double>(n);
    if (mode == Alignment::Sim3 && var_x > 1e-18)
    {
        out.scale = svd.singularValues().dot(d) / var_x;
    }
    const Eigen::Vector3d t = my - out.scale * R * mx;
    mrpt::math::CMatrixDouble33 Rm;
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
        {
            Rm(r, c) = R(r, c);
        }
    }
    out.T_gt_est.setRotationMatrix(Rm);
    out.T_gt_est.x(t.x());
    out.T_gt_est.y(t.y());
    out.T_gt_est.z(t.z());
    return out;
}

SimilarityTransform alignPoses(
    const std::vector<mrpt::poses::CPose3D>& gt,
    const std::vector<mrpt::poses::CPose3D>& est,
    Alignment mode,
    double lever_m)
{
    const double scale = alignPositions(gt, est, mode).scale;
    std::vector<mrpt::poses::CPose3D> g, e;
    g.reserve(4 * gt.size());
    e.reserve(4 * est.size());
    const auto addWithAxes =
        [](std::vector<mrpt::poses::CPose3D>& out, const mrpt::poses::CPose3D& pose, double lever)
    {
        out.push_back(pose);
        out.push_back(pose + mrpt::poses::CPose3D(lever, 0, 0, 0, 0, 0));
        out.push_back(pose + mrpt::poses::CPose3D(0, lever, 0, 0, 0, 0));
        out.push_back(pose + mrpt::poses::CPose3D(0, 0, lever, 0, 0, 0));
    };
    for (std::size_t i = 0; i < gt.size(); ++i)
    {
        addWithAxes(g, gt[i], lever_m);
        addWithAxes(e, est[i], scale > 0 ? lever_m / scale : lever_m);
    }
    return alignPositions(g, e, mode);
}

double pathLength(const std::vector<mrpt::poses::CPose3D>& poses)
{
    double len = 0;
    for (std::size_t i = 1; i < poses.size(); ++i)
    {
        len += poses[i].distanceTo(poses[i - 1]);
    }
    return len;
}

bool isClosedLoop(const emslam::io::TumTrajectory& t)
{
    if (t.size() < 2)
    {
        return false;
    }
    const double length = pathLength(t);
    const double gap = t.poses.front().pose.distanceTo(t.poses.back().pose);
    return length >= LOOP_MIN_PATH_M &&
           gap <= std::max(LOOP_TOLERANCE_FRACTION * length, LOOP_TOLERANCE_M);
}

double pathLength(const emslam::io::TumTrajectory& t)
{
    double length = 0;
    for (std::size_t i = 1; i < t.size(); ++i)
    {
        length += t.poses[i].pose.distanceTo(t.poses[i - 1].pose);
    }
    return length;
}

RelativeErrors relativeErrors(
    const std::vector<mrpt::poses::CPose3D>& gt,
    const std::vector<mrpt::poses::CPose3D>& est,
    std::size_t step)
{
    if (gt.size() != est.size())
    {
        throw std::invalid_argument("relativeErrors: trajectories of different lengths");
    }
    RelativeErrors out;
    const double total = pathLength(gt);
    if (total >= KITTI_LENGTHS[0])
    {
        out.lengths_m.assign(std::begin(KITTI_LENGTHS), std::end(KITTI_LENGTHS));
    }
    else if (total > 0)
    {
        for (const double f : SHORT_FRACTIONS)
        {
            out.lengths_m.push_back(f * total);
        }
    }
    // The mean over every segment of every length: the per-length means weighted by count.
    double sum_t = 0, sum_r = 0;
    for (const auto& s : segmentErrors(gt, est, out.lengths_m, step))
    {
        if (s.segments > 0)
        {
            const double n = static_cast<double>(s.segments);
            sum_t += s.t_err_percent * n;
            sum_r += s.r_err_deg_per_m * n;
            out.segments += s.segments;
        }
    }
    if (out.segments == 0)
    {
        out.t_rel_percent = out.r_rel_deg_per_m = UNDEFINED;
        return out;
    }
    const double n = static_cast<double>(out.segments);
    out.t_rel_percent = sum_t / n;
    out.r_rel_deg_per_m = sum_r / n;
    return out;
}

TrajectoryMetrics TrajectoryMetrics::compute(
    const emslam::io::TumTrajectory& gt, const emslam::io::TumTrajectory& est, const Options& opts)
{
    if (gt.empty())
    {
        throw std::runtime_error("the ground-truth trajectory has no poses");
    }
    if (est.empty())
    {
        throw std::runtime_error("the estimated trajectory has no poses");
    }
    TrajectoryMetrics m;
    m.alignment = opts.alignment;
    m.gt_poses = gt.size();
    m.est_poses = est.size();
    const AssociatedPoses a = associateByTimestamp(gt, est, opts.max_dt);
    m.matched_poses = a.size();
    if (a.size() == 0)
    {
        const auto span = [](const emslam::io::TumTrajectory& t)
        {
            const auto [lo, hi] = std::minmax_element(
                t.poses.begin(), t.poses.end(),
                [](const auto& p, const auto& q) { return p.t < q.t; });
            return "[" + emslam::io::shortestFixed(lo->t) + ", " +
                   emslam::io::shortestFixed(hi->t) + "] s";
        };
        std::ostringstream s;
        s << "no timestamp of the estimate matches the ground truth within max_dt = "
          << emslam::io::shortestFixed(opts.max_dt) << " s (estimate " << span(est)
          << ", ground truth " << span(gt) << ")";
        throw std::runtime_error(s.str());
    }

    m.align = alignPositions(a.gt, a.est, opts.alignment);
    m.map_align = alignPoses(a.gt, a.est, opts.alignment);
    std::vector<mrpt::poses::CPose3D> aligned;
    aligned.reserve(a.size());
    double sq = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        aligned.push_back(m.align.apply(a.est[i]));
        sq += aligned.back().sqrDistanceTo(a.gt[i]);
    }
    m.ate_rmse_m = std::sqrt(sq / static_cast<double>(a.size()));
    if (!std::isfinite(m.ate_rmse_m))
    {
        // Only absurd coordinates get here (loadTrajectoryInput() refuses them).
        throw std::runtime_error(
            "the ATE is not finite: a position of the estimate or the ground truth is absurd");
    }
    m.rel = relativeErrors(a.gt, aligned, opts.segment_step);
    m.segment_errors =
        segmentErrors(a.gt, aligned, segmentLengthsFor(pathLength(a.gt)), opts.segment_step);
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        m.error_time_s.push_back(a.t_gt[i] - a.t_gt.front());
        m.position_error_m.push_back(aligned[i].distanceTo(a.gt[i]));
    }
    // Anchor the estimate on the ground truth at the first pair: drift from the start.
    const mrpt::poses::CPose3D d_est = aligned.back() - aligned.front();
    m.end_error_m = (a.gt.front() + d_est).distanceTo(a.gt.back());
    const auto oe = timeOrder(est);
    m.loop_gap_m = m.align.scale * est.poses[oe.front()].pose.distanceTo(est.poses[oe.back()].pose);
    m.path_length_m = pathLength(a.gt);
    m.est_path_length_m = pathLength(aligned);
    return m;
}

std::string TrajectoryMetrics::toJson() const
{
    std::string lengths;
    for (const double l : rel.lengths_m)
    {
        lengths += (lengths.empty() ? "" : ", ") + io::jsonNumber(l);
    }
    std::ostringstream s;
    s << "{\n"
      << "  \"alignment\": \"" << alignmentName(alignment) << "\",\n"
      << "  \"gt_poses\": " << gt_poses << ",\n"
      << "  \"est_poses\": " << est_poses << ",\n"
      << "  \"matched_poses\": " << matched_poses << ",\n"
      << "  \"scale\": " << io::jsonNumber(align.scale) << ",\n"
      << "  \"ate_rmse_m\": " << io::jsonNumber(ate_rmse_m) << ",\n"
      << "  \"t_rel_percent\": " << io::jsonNumber(rel.t_rel_percent) << ",\n"
      << "  \"r_rel_deg_per_m\": " << io::jsonNumber(rel.r_rel_deg_per_m) << ",\n"
      << "  \"segments\": " << rel.segments << ",\n"
      << "  \"segment_lengths_m\": [" << lengths << "],\n"
      << "  \"end_error_m\": " << io::jsonNumber(end_error_m) << ",\n"
      << "  \"loop_gap_m\": " << io::jsonNumber(loop_gap_m) << ",\n"
      << "  \"path_length_m\": " << io::jsonNumber(path_length_m) << ",\n"
      << "  \"est_path_length_m\": " << io::jsonNumber(est_path_length_m) << "\n"
      << "}\n";
    return s.str();
}

}  // namespace emslam::eval
