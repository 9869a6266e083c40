// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/PoseGraph.h>
#include <emslam/slam/LevelFloors.h>
#include <emslam/slam/LoopCloser.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace emslam::slam
{
namespace
{
using Vec3 = Eigen::Vector3d;
/** Three standard deviations: the gates of a Gaussian's bulk. */
constexpr double GATE_SIGMAS = 3.0;
/** The same bulk (99.73 %) of a χ² with 6 degrees of freedom: a gate on the
 * Mahalanobis distance of a 6D pose difference. */
constexpr double GATE_CHI2_6DOF = 20.06;

Vec3 positionOf(const mrpt::poses::CPose3D& p)
{
    return {p.x(), p.y(), p.z()};
}

Vec3 viewingDirection(const mrpt::poses::CPose3D& p)
{
    const auto& R = p.getRotationMatrix();
    return {R(0, 2), R(1, 2), R(2, 2)};  // the camera's optical axis (z)
}

double translationTrace(const emslam::rectify::ActionCovariance& c)
{
    return c(0, 0) + c(1, 1) + c(2, 2);
}

double rotationTrace(const emslam::rectify::ActionCovariance& c)
{
    return c(3, 3) + c(4, 4) + c(5, 5);
}

/** How far the egomotion chain between two keyframes may have drifted: its
 * steps' translation variances plus each step's rotation variance times the
 * squared lever arm to the end point (first order), via prefix sums. Once
 * loop edges are accepted, a path may take one of them as a shortcut: the
 * drift between two keyframes is that of the best such path (an upper bound
 * of the graph's own). */
class ChainDrift
{
public:
    /** A shortcut: an accepted loop edge between keyframes a and b. */
    struct Shortcut
    {
        std::size_t a{0}, b{0};
        double variance_t{0}, variance_r{0};
    };

    ChainDrift(
        const std::vector<mrpt::poses::CPose3D>& poses,
        const std::vector<emslam::rectify::ActionCovariance>& steps,
        std::vector<Shortcut> shortcuts)
        : m_shortcuts(std::move(shortcuts))
    {
        const std::size_t n = poses.size();
        m_t.assign(n, 0.0);
        m_r.assign(n, 0.0);
        m_rp.assign(n, Vec3::Zero());
        m_rpp.assign(n, 0.0);
        for (std::size_t k = 1; k < n; ++k)
        {
            // Step k turns about keyframe k-1 everything after it.
            const Vec3 p = positionOf(poses[k - 1]);
            const double tr = std::max(0.0, rotationTrace(steps[k]));
            m_t[k] = m_t[k - 1] + std::max(0.0, translationTrace(steps[k]));
            m_r[k] = m_r[k - 1] + tr;
            m_rp[k] = m_rp[k - 1] + tr * p;
            m_rpp[k] = m_rpp[k - 1] + tr * p.squaredNorm();
        }
    }
    /** Variance of the position of `end` [m²] between keyframes a and b. */
    double translationVariance(std::size_t a, std::size_t b, const Vec3& end) const
    {
        double best = chainT(a, b, end);
        for (const auto& s : m_shortcuts)
        {
            best = std::min(
                best, std::min(
                          chainT(a, s.a, end) + s.variance_t + chainT(s.b, b, end),
                          chainT(a, s.b, end) + s.variance_t + chainT(s.a, b, end)));
        }
        return best;
    }
    /** Variance of the rotation between keyframes a and b [rad²]. */
    double rotationVariance(std::size_t a, std::size_t b) const
    {
        double best = chainR(a, b);
        for (const auto& s : m_shortcuts)
        {
            best = std::min(
                best, std::min(
                          chainR(a, s.a) + s.variance_r + chainR(s.b, b),
                          chainR(a, s.b) + s.variance_r + chainR(s.a, b)));
        }
        return best;
    }

private:
    double chainT(std::size_t a, std::size_t b, const Vec3& end) const
    {
        if (b < a)
        {
            std::swap(a, b);
        }
        const double r = m_r[b] - m_r[a];
        const Vec3 rp = m_rp[b] - m_rp[a];
        const double rpp = m_rpp[b] - m_rpp[a];
        return (m_t[b] - m_t[a]) + std::max(0.0, end.squaredNorm() * r - 2 * end.dot(rp) + rpp);
    }
    double chainR(std::size_t a, std::size_t b) const
    {
        return std::abs(m_r[std::max(a, b)] - m_r[std::min(a, b)]);
    }

    std::vector<double> m_t, m_r, m_rpp;
    std::vector<Vec3> m_rp;
    std::vector<Shortcut> m_shortcuts;
};

/** A registration of keyframe j in keyframe i. */
struct Registration
{
    std::size_t i{0}, j{0};
    bool ok{false};
    mrpt::poses::CPose3D z;  //!< pose of j in i
    emslam::rectify::ActionCovariance covariance;
    std::size_t matches{0};
    bool accepted{false};
    // Per round:
    double normalized{0};  //!< squared correction over its variance
    Vec3 correction;       //!< where i puts j minus where j is (world)
};
}  // namespace

void LoopCloser::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(min_path_length, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_distance, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_angle_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_candidates, int, c, s);
    MRPT_LOAD_CONFIG_VAR(max_rounds, int, c, s);
    MRPT_LOAD_CONFIG_VAR(local_edges, int, c, s);
    MRPT_LOAD_CONFIG_VAR(vertical_prior, bool, c, s);
    vertical.loadFromConfigFile(c, s);
    validate();
}

void LoopCloser::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    MRPT_SAVE_CONFIG_VAR_COMMENT(enabled, "close loops by registering revisited places");
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_path_length, "[m] path between two keyframes of a loop");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_distance, "[m] beyond the drift: views that still overlap");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_angle_deg, "[deg] between the viewing directions");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_candidates, "registrations per keyframe, nearest first");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_rounds, "rounds of detection and solving");
    MRPT_SAVE_CONFIG_VAR_COMMENT(local_edges, "direct registrations to the keyframes before");
    MRPT_SAVE_CONFIG_VAR_COMMENT(vertical_prior, "level floors: the up each keyframe sees");
    vertical.saveToConfigFile(c, s);
}

void LoopCloser::TParameters::validate() const
{
    const auto bad = [](const std::string& key, const std::string& why)
    { throw std::invalid_argument("[LoopCloser] " + key + ": " + why); };
    if (!(min_path_length >= 0) || !std::isfinite(min_path_length))
    {
        bad("min_path_length", "must be a length >= 0 m");
    }
    if (!(max_distance >= 0) || !std::isfinite(max_distance))
    {
        bad("max_distance", "must be a distance >= 0 m");
    }
    if (!(max_angle_deg > 0 && max_angle_deg <= 180))
    {
        bad("max_angle_deg", "must be in (0, 180] degrees");
    }
    if (max_candidates < 1)
    {
        bad("max_candidates", "must be >= 1");
    }
    if (max_rounds < 1)
    {
        bad("max_rounds", "must be >= 1");
    }
    if (local_edges < 0)
    {
        bad("local_edges", "must be >= 0");
    }
    try
    {
        vertical.validate();
    }
    catch (const std::invalid_argument& e)
    {
        throw std::invalid_argument(std::string("[LoopCloser] ") + e.what());
    }
}

LoopCloser::LoopCloser(const TParameters& p) : m_p((p.validate(), p)), m_vertical(m_p.vertical) {}

void LoopCloser::addKeyframe(
    std::size_t frame_index,
    emslam::egomotion::EgomotionEstimator::Description description,
    const emslam::rectify::ActionCovariance& step_covariance,
    const std::optional<mrpt::poses::CPose3D>& step_motion)
{
    m_keyframes.push_back(
        {frame_index, std::move(description), step_covariance, step_motion, std::nullopt});
}

void LoopCloser::observeVertical(
    std::size_t frame_index,
    const emslam::stereo::StereoFrame& frame,
    const mrpt::poses::CPose3D& pose)
{
    if (!m_p.vertical_prior)
    {
        return;
    }
    auto it = std::find_if(
        m_keyframes.rbegin(), m_keyframes.rend(),
        [frame_index](const Keyframe& k) { return k.frame_index == frame_index; });
    if (it == m_keyframes.rend())
    {
        return;
    }
    // Where up should be in this camera: the ups seen so far (world), or
    // the first camera's -y.
    const Vec3 sum(m_up_sum.x, m_up_sum.y, m_up_sum.z);
    const Vec3 g = sum.norm() > 0 ? sum.normalized() : Vec3(0, -1, 0);
    const auto R = pose.getRotationMatrix().asEigen();
    const Vec3 predicted = R.transpose() * g;
    it->vertical = m_vertical.measure(frame, {predicted.x(), predicted.y(), predicted.z()});
    if (it->vertical)
    {
        const auto& m = *it->vertical;
        const double var = m.covariance(0, 0) + m.covariance(1, 1) + m.covariance(2, 2);
        const Vec3 added = sum + R * Vec3(m.up.x, m.up.y, m.up.z) / std::max(var, 1e-12);
        m_up_sum = {added.x(), added.y(), added.z()};
    }
}

void LoopCloser::addLocalEdges(
    emslam::rectify::PoseGraph& graph,
    const std::vector<emslam::rectify::ActionCovariance>& steps,
    const emslam::rectify::ActionCovariance& mean_step,
    const emslam::egomotion::EgomotionEstimator& estimator)
{
    if (m_p.local_edges <= 0)
    {
        return;
    }
    const std::vector<mrpt::poses::CPose3D>& x = graph.nodes();
    const std::size_t depth = static_cast<std::size_t>(m_p.local_edges);
    for (std::size_t j = 1; j < x.size(); ++j)
    {
        if (!m_keyframes[j].description)
        {
            continue;
        }
        for (std::size_t i = j - std::min(j, depth); i < j; ++i)
        {
            if (!m_keyframes[i].description)
            {
                continue;
            }
            const auto r =
                estimator.estimate(m_keyframes[i].description, m_keyframes[j].description);
            ++m_stats.local_registrations;
            if (!r.ok)
            {
                continue;
            }
            const emslam::rectify::ActionCovariance cov =
                r.has_covariance ? r.covariance : mean_step;
            // Against the egomotion's own chain from i to j and its
            // covariance composed step by step: a registration must agree
            // with it in every direction, not only on the whole (an edge
            // confident across the path but off along it would bend the
            // path), and not with the rectified chain, which the edge may
            // have to correct.
            emslam::rectify::ActionCovariance chain;
            chain.setZero();
            mrpt::poses::CPose3D T_i_k;
            for (std::size_t k = i + 1; k <= j; ++k)
            {
                const auto& motion = m_keyframes[k].motion;
                const mrpt::poses::CPose3D step = motion ? *motion : x[k] - x[k - 1];
                chain = emslam::rectify::composeCovariance(T_i_k, chain, step, steps[k]);
                T_i_k = T_i_k + step;
            }
            const auto delta = emslam::rectify::actionDifference(T_i_k, r.T_prev_cur);
            const double d2 = 2 * emslam::rectify::halfMahalanobis(
                                      delta, emslam::rectify::informationOf(chain + cov, 6));
            if (!(d2 <= GATE_CHI2_6DOF))
            {
                continue;
            }
            graph.addEdge(i, j, r.T_prev_cur, cov);
            ++m_stats.local_edges;
        }
    }
    if (m_stats.local_edges > 0)
    {
        const auto solved = graph.optimize();
        m_stats.initial_cost = solved.initial_cost;
        m_stats.final_cost = solved.final_cost;
    }
}

std::vector<mrpt::poses::CPose3D> LoopCloser::close(
    const std::vector<mrpt::poses::CPose3D>& poses,
    const emslam::egomotion::EgomotionEstimator& estimator)
{
    const auto t0 = std::chrono::steady_clock::now();
    m_stats = Stats{};
    m_edges.clear();
    const std::size_t n = m_keyframes.size();
    if (poses.size() != n)
    {
        throw std::invalid_argument(
            "LoopCloser::close: " + std::to_string(poses.size()) + " poses for " +
            std::to_string(n) + " keyframes");
    }
    if (n < 3)
    {
        return poses;
    }
    emslam::rectify::PoseGraph graph;
    std::vector<emslam::rectify::ActionCovariance> steps(n);
    std::vector<double> path(n, 0.0);
    for (std::size_t k = 0; k < n; ++k)
    {
        graph.addNode(poses[k]);
        steps[k] = m_keyframes[k].covariance;
        if (k > 0)
        {
            graph.addEdge(k - 1, k, poses[k] - poses[k - 1], steps[k]);
            path[k] = path[k - 1] + (positionOf(poses[k]) - positionOf(poses[k - 1])).norm();
        }
    }
    emslam::rectify::ActionCovariance mean_step;
    mean_step.setZero();
    for (std::size_t k = 1; k < n; ++k)
    {
        mean_step += steps[k];
    }
    mean_step *= 1.0 / static_cast<double>(n - 1);
    addLocalEdges(graph, steps, mean_step, estimator);
    const double cos_max_angle = std::cos(mrpt::DEG2RAD(m_p.max_angle_deg));
    std::map<std::pair<std::size_t, std::size_t>, Registration> tried;
    std::vector<ChainDrift::Shortcut> shortcuts;
    for (int round = 0; round < m_p.max_rounds; ++round)
    {
        const std::vector<mrpt::poses::CPose3D>& x = graph.nodes();
        const ChainDrift drift(x, steps, shortcuts);
        // 1-2. Candidates by the current poses; new pairs are registered.
        for (std::size_t j = 1; j < n; ++j)
        {
            if (!m_keyframes[j].description)
            {
                continue;
            }
            const Vec3 pj = positionOf(x[j]);
            std::vector<std::pair<double, std::size_t>> near;
            for (std::size_t i = 0; i < j && path[j] - path[i] >= m_p.min_path_length; ++i)
            {
                if (!m_keyframes[i].description ||
                    viewingDirection(x[i]).dot(viewingDirection(x[j])) < cos_max_angle)
                {
                    continue;
                }
                const double d = (positionOf(x[i]) - pj).norm();
                const double sigma = std::sqrt(drift.translationVariance(i, j, pj));
                if (d <= m_p.max_distance + GATE_SIGMAS * sigma)
                {
                    near.emplace_back(d, i);
                }
            }
            m_stats.candidates += near.size();
            std::sort(near.begin(), near.end());
            near.resize(std::min(near.size(), static_cast<std::size_t>(m_p.max_candidates)));
            for (const auto& [d, i] : near)
            {
                if (tried.count({i, j}) != 0)
                {
                    continue;
                }
                Registration reg;
                reg.i = i;
                reg.j = j;
                const auto r =
                    estimator.estimate(m_keyframes[i].description, m_keyframes[j].description);
                ++m_stats.registrations;
                reg.ok = r.ok;
                reg.z = r.T_prev_cur;
                // A registration is one more egomotion step: without a
                // curvature of its own (e.g. a perfect fit), it gets theirs.
                reg.covariance = r.has_covariance ? r.covariance : mean_step;
                reg.matches = r.final_matches;
                tried[{i, j}] = reg;
            }
        }
        // Gate every registration not yet accepted against the current poses.
        std::vector<Registration*> gated;
        for (auto& [key, reg] : tried)
        {
            if (!reg.ok || reg.accepted)
            {
                continue;
            }
            const Vec3 pj = positionOf(x[reg.j]);
            const auto delta = emslam::rectify::actionDifference(x[reg.j] - x[reg.i], reg.z);
            const double dt2 = delta[0] * delta[0] + delta[1] * delta[1] + delta[2] * delta[2];
            const double dr2 = delta[3] * delta[3] + delta[4] * delta[4] + delta[5] * delta[5];
            const double var_t =
                drift.translationVariance(reg.i, reg.j, pj) + translationTrace(reg.covariance);
            const double var_r =
                drift.rotationVariance(reg.i, reg.j) + rotationTrace(reg.covariance);
            if (dt2 > GATE_SIGMAS * GATE_SIGMAS * var_t || dr2 > GATE_SIGMAS * GATE_SIGMAS * var_r)
            {
                continue;
            }
            reg.normalized = dt2 / var_t + dr2 / var_r;
            reg.correction = positionOf(x[reg.i] + reg.z) - pj;
            gated.push_back(&reg);
        }
        if (round == 0)
        {
            m_stats.registered = gated.size();
        }
        std::sort(
            gated.begin(), gated.end(),
            [](const Registration* a, const Registration* b)
            { return a->normalized < b->normalized; });
        // 3. Consensus: the first registration, by normalised correction,
        // that another one agrees with.
        std::vector<Registration*> winners;
        for (const Registration* seed : gated)
        {
            winners.clear();
            for (Registration* r : gated)
            {
                const Vec3 at_j = positionOf(x[std::max(seed->j, r->j)]);
                const Vec3 at_i = positionOf(x[std::max(seed->i, r->i)]);
                const double var = drift.translationVariance(seed->j, r->j, at_j) +
                                   drift.translationVariance(seed->i, r->i, at_i) +
                                   translationTrace(seed->covariance) +
                                   translationTrace(r->covariance);
                if ((r->correction - seed->correction).squaredNorm() <=
                    GATE_SIGMAS * GATE_SIGMAS * var)
                {
                    winners.push_back(r);
                }
            }
            if (winners.size() >= 2)
            {
                break;
            }
            winners.clear();
        }
        if (winners.empty())
        {
            break;
        }
        // 4. Into the graph, and solve.
        for (Registration* r : winners)
        {
            r->accepted = true;
            shortcuts.push_back(
                {r->i, r->j, translationTrace(r->covariance), rotationTrace(r->covariance)});
            graph.addEdge(r->i, r->j, r->z, r->covariance);
            m_edges.push_back(
                {m_keyframes[r->i].frame_index, m_keyframes[r->j].frame_index, r->z, r->matches});
        }
        const auto solved = graph.optimize();
        if (m_stats.rounds == 0 && m_stats.local_edges == 0)
        {
            m_stats.initial_cost = solved.initial_cost;
        }
        m_stats.final_cost = solved.final_cost;
        m_stats.rounds = round + 1;
    }
    m_stats.loop_edges = m_edges.size();
    if (m_p.vertical_prior)
    {
        // How far the egomotion may have tilted each keyframe: its chain's
        // rotation variance, per axis (no loop or local edge counted).
        std::vector<std::optional<emslam::stereo::VerticalMeasurement>> verticals(n);
        std::vector<double> tilt_variance(n, 0.0);
        for (std::size_t k = 0; k < n; ++k)
        {
            verticals[k] = m_keyframes[k].vertical;
            if (k > 0)
            {
                tilt_variance[k] = tilt_variance[k - 1] + rotationTrace(steps[k]) / 3;
            }
        }
        const LevelFloorsStats level = levelFloors(graph, verticals, tilt_variance);
        m_stats.verticals_measured = level.measured;
        m_stats.verticals_used = level.used;
        m_stats.vertical_drift_deg = level.drift_deg;
        m_stats.vertical_bias_deg = level.bias_deg;
        m_stats.vertical_correlation_time = level.correlation_time;
    }
    m_stats.ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return graph.nodes();
}

}  // namespace emslam::slam
