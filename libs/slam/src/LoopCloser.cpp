// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/rectify/PoseGraph.h>
#include <emslam/slam/LevelFloors.h>
#include <emslam/slam/LoopCloser.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <unordered_map>
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

/** Edge tags in the pose graph: odometry, local, and loop edges (the loop
 * edge's index in loopEdges() added to EDGE_LOOP). */
constexpr std::size_t EDGE_ODOMETRY = 0;
constexpr std::size_t EDGE_LOCAL = 1;
constexpr std::size_t EDGE_LOOP = 2;
/** Levenberg–Marquardt iterations of a solve during the run (from where the
 * graph is: a few suffice) and of the polish. */
constexpr int ONLINE_ITERATIONS = 8;
constexpr int POLISH_ITERATIONS = 30;
/** After new rectified odometry: the rectifier moves the path a little. */
constexpr int RECTIFIED_ITERATIONS = 3;
/** No keyframe waits for a solve. */
constexpr std::size_t NONE_UNSOLVED = std::numeric_limits<std::size_t>::max();
/** A rectified odometry edge that moved less than this Mahalanobis² from
 * what the graph had does not make its keyframes free in that solve. */
constexpr double RECTIFIED_CHANGE_MIN = 0.01;
/** A solve stops once an iteration lowers the cost by less than this
 * fraction: far below the noise of any edge. */
constexpr double SOLVE_TOLERANCE = 1e-6;
/** The polish stops once the step left would lower the cost (½χ²) by less
 * than this: δᵀHδ < ¼, a step of less than half a standard deviation of any
 * quantity the graph estimates (Cauchy–Schwarz in the metric of H). The
 * 4-lap hall's polish freed 1,281 keyframes and spent three of its four
 * iterations (0.3 s) lowering the cost by 0.04. */
constexpr double POLISH_MIN_DECREASE = 0.125;
/** Registrations that must agree for a loop to close (step 5). */
constexpr std::size_t CONSENSUS_MIN = 2;
/** Solves after dropping refused loop edges, at most. */
constexpr int MAX_DROP_PASSES = 3;
/** Times one look-alike place may fool the consensus (on the way in and on
 * the way out) before the world is taken for one of look-alikes. */
constexpr std::size_t LOOK_ALIKE_FOOLS = 2;
/** How often a χ² test at GATE_CHI2_6DOF fails by chance. */
constexpr double GATE_FALSE_ALARM = 1.0 - 0.9973;

/** The 99.73 % quantile of a Poisson count of mean `mean`: more events than
 * this are not chance. */
std::size_t poissonBulk(double mean)
{
    double term = std::exp(-mean), cdf = term;
    std::size_t k = 0;
    while (cdf < 0.9973 && k < 1000000)
    {
        ++k;
        term *= mean / static_cast<double>(k);
        cdf += term;
    }
    return k;
}

/** The median of a χ² with 6 degrees of freedom: what the median Mahalanobis²
 * of the local registrations would be if the egomotion's covariance were
 * right. */
constexpr double CHI2_6DOF_MEDIAN = 5.348;
/** Local registrations whose misclosures calibrate the drift (the most
 * recent), and how many before the calibration is trusted. */
constexpr std::size_t MISCLOSURE_SAMPLES = 256;
constexpr std::size_t MISCLOSURE_MIN_SAMPLES = 16;
/** Features of a keyframe the place recognition indexes when the keyframes
 * keep every feature (kept_features = 0). */
constexpr std::size_t PLACE_FEATURES = 200;

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

/** The squared norm of d[from .. from + 2] (translation: 0, rotation: 3). */
double squaredNorm3(const emslam::rectify::ActionDelta& d, int from)
{
    return d[from] * d[from] + d[from + 1] * d[from + 1] + d[from + 2] * d[from + 2];
}

/** How far the egomotion chain between two keyframes may have drifted: its
 * steps' translation variances plus each step's rotation variance times the
 * squared lever arm to the end point (first order), via prefix sums. Once
 * loop edges are accepted, a path may take one of them as a shortcut: the
 * drift between two keyframes is that of the best such path (an upper bound
 * of the graph's own). */
}  // namespace

/** How far the egomotion chain between two keyframes may have drifted: its
 * steps' translation variances plus each step's rotation variance times the
 * squared lever arm to the end point (first order), via prefix sums grown
 * one keyframe at a time. A path may take an accepted loop edge as a
 * shortcut: the drift between two keyframes is that of the best such path
 * (an upper bound of the graph's own), over the most recent shortcuts only,
 * which bounds the cost of a query. */
class LoopCloser::Drift
{
public:
    static constexpr std::size_t MAX_SHORTCUTS = 32;

    /** The step from a keyframe at `previous_position`, with its
     * covariance, and variances the egomotion did not count (a step it
     * predicted instead of measuring) [m², rad²]. */
    void append(
        const Vec3& previous_position,
        const emslam::rectify::ActionCovariance& step,
        double unmeasured_t = 0,
        double unmeasured_r = 0)
    {
        if (m_t.empty())
        {
            m_t.push_back(0);
            m_r.push_back(0);

            m_rp.push_back(Vec3::Zero());
            m_rpp.push_back(0);
            return;
        }
        const double tr = std::max(0.0, rotationTrace(step)) + unmeasured_r;
        m_t.push_back(m_t.back() + std::max(0.0, translationTrace(step)) + unmeasured_t);
        m_r.push_back(m_r.back() + tr);
        m_rp.push_back(m_rp.back() + tr * previous_position);
        m_rpp.push_back(m_rpp.back() + tr * previous_position.squaredNorm());
    }
    /** The chain's variances are the egomotion's times `scale` (>= 1): by
     * how much its covariance understates its error. */
    void setScale(double scale) { m_scale = scale; }
    double scale() const { return m_scale; }
    void addShortcut(std::size_t a, std::size_t b, double variance_t, double variance_r)
    {
        m_shortcuts.push_back({a, b, variance_t, variance_r});
        if (m_shortcuts.size() > MAX_SHORTCUTS)
        {
            m_shortcuts.erase(m_shortcuts.begin());
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
    struct Shortcut
    {
        std::size_t a{0}, b{0};
        double variance_t{0}, variance_r{0};
    };
    double chainT(std::size_t a, std::size_t b, const Vec3& end) const
    {
        if (b < a)
        {
            std::swap(a, b);
        }
        const double r = m_r[b] - m_r[a];
        const Vec3 rp = m_rp[b] - m_rp[a];
        const double rpp = m_rpp[b] - m_rpp[a];
        return m_scale *
               ((m_t[b] - m_t[a]) + std::max(0.0, end.squaredNorm() * r - 2 * end.dot(rp) + rpp));
    }
    double chainR(std::size_t a, std::size_t b) const
    {
        return m_scale * std::abs(m_r[std::max(a, b)] - m_r[std::min(a, b)]);
    }

    std::vector<double> m_t, m_r, m_rpp;
    std::vector<Vec3> m_rp;
    std::vector<Shortcut> m_shortcuts;
    double m_scale{1};
};

/** The keyframe positions in cubic cells, so that the keyframes near a
 * place are found without looking at all of them. */
class LoopCloser::Grid
{
public:
    explicit Grid(double cell) : m_cell(cell) {}

    void insert(std::size_t k, const Vec3& p) { m_cells[keyOf(p)].push_back(k); }
    void rebuild(const std::vector<mrpt::poses::CPose3D>& nodes)
    {
        m_cells.clear();
        for (std::size_t k = 0; k < nodes.size(); ++k)
        {
            insert(k, positionOf(nodes[k]));
        }
    }
    /** Calls `visit(k)` for every keyframe in a cell the ball (c, radius)
     * touches: the cells of its bounding box, or the occupied cells if
     * there are fewer of them. */
    template <typename Visit>
    void near(const Vec3& c, double radius, Visit&& visit) const
    {
        const double cells_per_side = std::ceil(2 * radius / m_cell) + 1;
        if (cells_per_side * cells_per_side * cells_per_side > static_cast<double>(m_cells.size()))
        {
            for (const auto& [key, ks] : m_cells)
            {
                for (std::size_t k : ks)
                {
                    visit(k);
                }
            }
            return;
        }
        const auto lo = cellOf(c - Vec3::Constant(radius));
        const auto hi = cellOf(c + Vec3::Constant(radius));
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
        {
            for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
            {
                for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
                {
                    const auto it = m_cells.find(pack(x, y, z));
                    if (it != m_cells.end())
                    {
                        for (std::size_t k : it->second)
                        {
                            visit(k);
                        }
                    }
                }
            }
        }
    }

private:
    std::array<std::int64_t, 3> cellOf(const Vec3& p) const
    {
        return {
            static_cast<std::int64_t>(std::floor(p.x() / m_cell)),
            static_cast<std::int64_t>(std::floor(p.y() / m_cell)),
            static_cast<std::int64_t>(std::floor(p.z() / m_cell))};
    }
    static std::int64_t pack(std::int64_t x, std::int64_t y, std::int64_t z)
    {
        constexpr std::int64_t MASK = (std::int64_t{1} << 21) - 1;
        return ((x & MASK) << 42) | ((y & MASK) << 21) | (z & MASK);
    }
    std::int64_t keyOf(const Vec3& p) const
    {
        const auto c = cellOf(p);
        return pack(c[0], c[1], c[2]);
    }

    double m_cell;
    std::unordered_map<std::int64_t, std::vector<std::size_t>> m_cells;
};

/** A registration of keyframe j in keyframe i. */
struct LoopCloser::Registration
{
    std::size_t i{0}, j{0};
    mrpt::poses::CPose3D z;  //!< pose of j in i
    emslam::rectify::ActionCovariance covariance;
    std::size_t matches{0};
    std::size_t tag{0};  //!< once accepted: its edge's
    // At the current poses:
    double normalized{0};  //!< squared correction over its variance
    Vec3 correction;       //!< where i puts j minus where j is (world)
    /** What the graph disagreed with its edge before the group was solved. */
    emslam::rectify::ActionDelta misclosure{};
};

namespace
{
/** Every key of the section, once for load and save. */
void visit(LoopCloser::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("enabled", p.enabled, "close loops by registering revisited places");
    v.field("min_path_length", p.min_path_length, "[m] path between two keyframes of a loop");
    v.field("max_distance", p.max_distance, "[m] beyond the drift: views that still overlap");
    v.field("max_angle_deg", p.max_angle_deg, "[deg] between the viewing directions");
    v.field("max_candidates", p.max_candidates, "registrations per keyframe, nearest first");
    v.field(
        "place_candidates", p.place_candidates,
        "look-alike keyframes registered first, whatever the drift (0: off)");
    v.field("local_edges", p.local_edges, "direct registrations to the keyframes before");
    v.field("vertical_prior", p.vertical_prior, "level floors: the up each keyframe sees");
    v.field(
        "vertical_max_bias_deg", p.vertical_max_bias_deg,
        "[deg] largest tilt of the camera's own bias in the ups");
    v.field("kept_features", p.kept_features, "features kept per keyframe, 8-bit (0: all, float)");
    v.field("consensus_window", p.consensus_window, "keyframes whose registrations may agree");
    v.field("max_lag", p.max_lag, "keyframes loop closing may lag before the mapper waits");
    v.field(
        "max_lag_ms", p.max_lag_ms,
        "[ms] work loop closing may have left before the mapper waits (0: max_lag only)");
}
}  // namespace

void LoopCloser::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void LoopCloser::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
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
    if (place_candidates < 0)
    {
        bad("place_candidates", "must be >= 0 (0: off)");
    }
    if (local_edges < 0)
    {
        bad("local_edges", "must be >= 0");
    }
    if (kept_features < 0)
    {
        bad("kept_features", "must be >= 0 (0: every feature)");
    }
    if (consensus_window < 1)
    {
        bad("consensus_window", "must be >= 1 keyframe");
    }
    if (max_lag < 1)
    {
        bad("max_lag", "must be >= 1 keyframe");
    }
    if (!(max_lag_ms >= 0) || !std::isfinite(max_lag_ms))
    {
        bad("max_lag_ms", "must be a time >= 0 ms (0: max_lag only)");
    }
    if (!(vertical_max_bias_deg >= 0 && vertical_max_bias_deg <= 30))
    {
        bad("vertical_max_bias_deg", "must be in [0, 30] degrees (0: no bias solved)");
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

LoopCloser::LoopCloser(const TParameters& p)
    : m_p((p.validate(), p)),
      m_vertical(m_p.vertical),
      m_drift(std::make_unique<Drift>()),
      m_grid(std::make_unique<Grid>(std::max(m_p.max_distance, 0.5)))
{
}

LoopCloser::~LoopCloser() = default;

void LoopCloser::addKeyframe(
    std::size_t frame_index,
    emslam::egomotion::EgomotionEstimator::Description description,
    const emslam::rectify::ActionCovariance& step_covariance,
    const std::optional<mrpt::poses::CPose3D>& step_motion,
    bool step_predicted)
{
    Keyframe k;
    k.frame_index = frame_index;
    k.description = std::move(description);
    k.covariance = step_covariance;
    k.motion = step_motion;
    k.predicted = step_predicted;
    k.added = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(m_in_mutex);
    m_incoming.push_back(std::move(k));
    ++m_added;
}

std::size_t LoopCloser::keyframeCount() const
{
    std::lock_guard<std::mutex> lock(m_in_mutex);
    return m_added;
}

std::size_t LoopCloser::processedCount() const
{
    std::lock_guard<std::mutex> lock(m_out_mutex);
    return m_published.size();
}

double LoopCloser::backlogMs() const
{
    const std::size_t added = keyframeCount();
    std::lock_guard<std::mutex> lock(m_out_mutex);
    return static_cast<double>(added - std::min(added, m_published.size())) * m_ms_per_keyframe;
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
    // Where up should be in this camera: the ups seen so far (world), or
    // the first camera's -y.
    const Vec3 sum(m_up_sum.x, m_up_sum.y, m_up_sum.z);
    const Vec3 g = sum.norm() > 0 ? sum.normalized() : Vec3(0, -1, 0);
    const auto R = pose.getRotationMatrix().asEigen();
    const Vec3 predicted = R.transpose() * g;
    const auto m = m_vertical.measure(frame, {predicted.x(), predicted.y(), predicted.z()});
    if (!m)
    {
        return;
    }
    const double var = m->covariance(0, 0) + m->covariance(1, 1) + m->covariance(2, 2);
    const Vec3 added = sum + R * Vec3(m->up.x, m->up.y, m->up.z) / std::max(var, 1e-12);
    m_up_sum = {added.x(), added.y(), added.z()};
    std::lock_guard<std::mutex> lock(m_in_mutex);
    m_incoming_verticals.emplace_back(frame_index, *m);
}

std::vector<LoopCloser::Keyframe> LoopCloser::takeIncoming()
{
    std::vector<Keyframe> taken;
    std::vector<std::pair<std::size_t, emslam::stereo::VerticalMeasurement>> verticals;
    {
        std::lock_guard<std::mutex> lock(m_in_mutex);
        taken.swap(m_incoming);
        verticals.swap(m_incoming_verticals);
    }
    for (auto& [frame, v] : verticals)
    {
        const auto it = m_keyframe_of_frame.find(frame);
        if (it != m_keyframe_of_frame.end())
        {
            m_keyframes[it->second].vertical = v;
            m_ungated_from = std::min(m_ungated_from, it->second);
            continue;
        }
        const auto in = std::find_if(
            taken.begin(), taken.end(),
            [f = frame](const Keyframe& k) { return k.frame_index == f; });
        if (in != taken.end())
        {
            in->vertical = v;
        }
    }
    return taken;
}

void LoopCloser::setRectifiedPoses(std::vector<KeyframePose> poses)
{
    std::lock_guard<std::mutex> lock(m_in_mutex);
    m_incoming_rectified = std::move(poses);
}

void LoopCloser::prepareToClose()
{
    std::lock_guard<std::mutex> lock(m_in_mutex);
    m_incoming_rectified.reset();
    m_closing = true;
}

std::size_t LoopCloser::applyRectified(const std::vector<KeyframePose>& poses)
{
    std::vector<const mrpt::poses::CPose3D*> by_keyframe(m_keyframes.size(), nullptr);
    for (const auto& p : poses)
    {
        const auto it = m_keyframe_of_frame.find(p.frame_index);
        if (it != m_keyframe_of_frame.end())
        {
            by_keyframe[it->second] = &p.pose;
        }
    }
    // The first keyframe whose odometry edge changes by more than a small
    // fraction of its own noise: those before it need not move.
    std::size_t first_changed = m_keyframes.size();
    for (std::size_t e = 0; e < m_graph.edges().size(); ++e)
    {
        const auto& edge = m_graph.edges()[e];
        // (A saved session's edges stay as it was saved.)
        if (edge.tag != EDGE_ODOMETRY || edge.to < m_seeded || !by_keyframe[edge.from] ||
            !by_keyframe[edge.to])
        {
            continue;
        }
        const mrpt::poses::CPose3D z = *by_keyframe[edge.to] - *by_keyframe[edge.from];
        const double d2 =
            2 * emslam::rectify::halfMahalanobis(
                    emslam::rectify::actionDifference(z, edge.measurement), edge.information);
        if (d2 > RECTIFIED_CHANGE_MIN)
        {
            first_changed = std::min(first_changed, edge.to);
        }
        m_graph.setEdgeMeasurement(e, z);
    }
    return first_changed;
}

std::size_t LoopCloser::update(
    const emslam::egomotion::EgomotionEstimator& estimator, const std::function<bool()>& stop)
{
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Keyframe> taken = takeIncoming();
    std::optional<std::vector<KeyframePose>> rectified;
    {
        std::lock_guard<std::mutex> lock(m_in_mutex);
        rectified.swap(m_incoming_rectified);
    }
    std::size_t done = 0;
    for (std::size_t n = 0; n < taken.size(); ++n)
    {
        Keyframe& k = taken[n];
        if (!m_keyframes.empty() && !k.motion)
        {
            // Not placeable without the poses close() is given: back in line.
            std::lock_guard<std::mutex> lock(m_in_mutex);
            m_incoming.insert(
                m_incoming.begin(), std::make_move_iterator(taken.begin() + static_cast<long>(n)),
                std::make_move_iterator(taken.end()));
            break;
        }
        const mrpt::poses::CPose3D T = k.motion ? *k.motion : mrpt::poses::CPose3D();
        integrate(std::move(k), T, estimator, !(stop && stop()));
        ++done;
    }
    const double keyframes_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const std::size_t first_changed =
        rectified && !(stop && stop()) ? applyRectified(*rectified) : m_keyframes.size();
    if (first_changed < m_keyframes.size())
    {
        // The ups seen since the last solve join it.
        relevel();
        // The rectifier moves the path a little at a time: a few iterations
        // from where the graph is, of the keyframes it moved (and those the
        // local edges added since the last solve reach).
        const std::size_t first_free = std::min(first_changed, m_unsolved_from);
        const auto solved = m_graph.optimize(
            RECTIFIED_ITERATIONS, first_free, SOLVE_TOLERANCE, 0,
            [this] { return m_closing.load(); });
        m_unsolved_from = NONE_UNSOLVED;
        leaveUnconverged(solved, RECTIFIED_ITERATIONS, first_free);
        m_solved_upto = m_keyframes.size();
        m_stats.final_cost = solved.final_cost;
        ++m_stats.rounds;
        m_stats.local_solves += first_free > 1 ? 1 : 0;
        m_grid->rebuild(m_graph.nodes());
        publishPoses(true);
    }
    m_stats.ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (done > 0)
    {
        // A keyframe's cost grows with the revisits it meets: the recent
        // ones count, each with the weight of one in 32. (Not the solves for
        // rectified poses: prepareToClose() cuts them short.)
        const double recent = std::pow(1.0 - 1.0 / 32, static_cast<double>(done));
        const double per_keyframe = keyframes_ms / static_cast<double>(done);
        std::lock_guard<std::mutex> lock(m_out_mutex);
        m_ms_per_keyframe = m_ms_per_keyframe == 0
                                ? per_keyframe
                                : recent * m_ms_per_keyframe + (1 - recent) * per_keyframe;
    }
    return done;
}

emslam::egomotion::EgomotionEstimator::Description LoopCloser::descriptionOf(std::size_t k) const
{
    const Keyframe& kf = m_keyframes[k];
    return kf.description ? kf.description : emslam::egomotion::EgomotionEstimator::expand(kf.kept);
}

void LoopCloser::integrate(
    Keyframe k,
    const mrpt::poses::CPose3D& T_prev_cur,
    const emslam::egomotion::EgomotionEstimator& estimator,
    bool work)
{
    using emslam::egomotion::EgomotionEstimator;
    const std::size_t j = m_keyframes.size();
    // 1. Node and odometry edge.
    const mrpt::poses::CPose3D pose =
        j == 0 ? mrpt::poses::CPose3D() : m_graph.node(j - 1) + T_prev_cur;
    m_graph.addNode(pose);
    // A step the egomotion predicted (it failed) may be off by as much as
    // any step it measured, whatever covariance the prediction was given:
    // the drift, where revisits are looked for, counts that. (Not its
    // odometry edge: a graph that free at the failed steps lets look-alikes
    // through the checks of step 6.)
    double unmeasured_t = 0, unmeasured_r = 0;
    if (k.predicted)
    {
        unmeasured_t = m_largest_step_t * m_largest_step_t;
        unmeasured_r = m_largest_step_r * m_largest_step_r;
    }
    else if (j > 0)
    {
        m_largest_step_t = std::max(m_largest_step_t, T_prev_cur.norm());
        m_largest_step_r = std::max(m_largest_step_r, emslam::rectify::rotationAngle(T_prev_cur));
    }
    m_drift->append(
        j == 0 ? Vec3::Zero() : positionOf(m_graph.node(j - 1)), k.covariance, unmeasured_t,
        unmeasured_r);
    m_path.push_back(
        j == 0 ? 0.0 : m_path.back() + (positionOf(pose) - positionOf(m_graph.node(j - 1))).norm());
    if (j > 0)
    {
        m_graph.addEdge(j - 1, j, T_prev_cur, k.covariance, EDGE_ODOMETRY);
    }
    m_keyframe_of_frame[k.frame_index] = j;
    const bool described = k.description != nullptr;
    if (described && m_p.kept_features > 0)
    {
        k.kept =
            EgomotionEstimator::compact(k.description, static_cast<std::size_t>(m_p.kept_features));
    }
    m_keyframes.push_back(std::move(k));
    bool solved = false;
    if (work && described)
    {
        addLocalEdges(j, estimator);
        registerCandidates(j, estimator);
        if (m_p.place_candidates > 0)
        {
            const auto t0 = std::chrono::steady_clock::now();
            m_places.add(j, m_place_words);
            m_stats.place_ms +=
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count();
            m_stats.place_index_bytes = m_places.bytes();
        }
        auto group = takeConsensusGroup(j, false);
        if (!group.empty())
        {
            solved = tryAccept(std::move(group));
        }
    }
    // Full descriptions only while a later keyframe's local edges need them.
    const std::size_t depth = static_cast<std::size_t>(m_p.local_edges);
    if (m_p.kept_features > 0 && j >= depth)
    {
        m_keyframes[j - depth].description = nullptr;
    }
    m_stats.kept_bytes += m_keyframes[j].kept.bytes();
    if (solved)
    {
        m_grid->rebuild(m_graph.nodes());
    }
    else
    {
        m_grid->insert(j, positionOf(pose));
    }
    publishPoses(solved);
}

void LoopCloser::addLocalEdges(
    std::size_t j, const emslam::egomotion::EgomotionEstimator& estimator)
{
    const std::size_t depth = static_cast<std::size_t>(m_p.local_edges);
    if (depth == 0 || j == 0)
    {
        return;
    }
    const auto cur = m_keyframes[j].description;
    for (std::size_t i = j - std::min(j, depth); i < j; ++i)
    {
        const auto prev = descriptionOf(i);
        if (!prev)
        {
            continue;
        }
        const auto r = estimator.estimate(prev, cur);
        ++m_stats.local_registrations;
        if (!r.ok)
        {
            continue;
        }
        const emslam::rectify::ActionCovariance cov =
            r.has_covariance ? r.covariance : m_keyframes[j].covariance;
        // Against the egomotion's own chain from i to j and its covariance
        // composed step by step: a registration must agree with it in every
        // direction, not only on the whole (an edge confident across the path
        // but off along it would bend the path).
        emslam::rectify::ActionCovariance chain;
        chain.setZero();
        mrpt::poses::CPose3D T_i_k;
        for (std::size_t k = i + 1; k <= j; ++k)
        {
            const auto& motion = m_keyframes[k].motion;
            const mrpt::poses::CPose3D step =
                motion ? *motion : m_graph.node(k) - m_graph.node(k - 1);
            chain =
                emslam::rectify::composeCovariance(T_i_k, chain, step, m_keyframes[k].covariance);
            T_i_k = T_i_k + step;
        }
        const auto delta = emslam::rectify::actionDifference(T_i_k, r.T_prev_cur);
        const double d2 = 2 * emslam::rectify::halfMahalanobis(
                                  delta, emslam::rectify::informationOf(chain + cov, 6));
        recordLocalMisclosure(d2);
        if (!(d2 <= GATE_CHI2_6DOF))
        {
            continue;
        }
        m_graph.addEdge(i, j, r.T_prev_cur, cov, EDGE_LOCAL);
        m_unsolved_from = std::min(m_unsolved_from, std::max<std::size_t>(i, 1));
        ++m_stats.local_edges;
    }
}

void LoopCloser::recordLocalMisclosure(double d2)
{
    if (!std::isfinite(d2))
    {
        return;
    }
    if (m_local_misclosures.size() < MISCLOSURE_SAMPLES)
    {
        m_local_misclosures.push_back(d2);
    }
    else
    {
        m_local_misclosures[m_local_misclosure_next] = d2;
        m_local_misclosure_next = (m_local_misclosure_next + 1) % MISCLOSURE_SAMPLES;
    }
    updateDriftScale();
}

void LoopCloser::updateDriftScale()
{
    if (m_local_misclosures.size() < MISCLOSURE_MIN_SAMPLES)
    {
        return;
    }
    // The median, robust to the registrations that failed outright: the
    // egomotion's variances times this is what its errors are.
    std::vector<double> sorted = m_local_misclosures;
    const auto mid = sorted.begin() + static_cast<long>(sorted.size() / 2);
    std::nth_element(sorted.begin(), mid, sorted.end());
    m_drift->setScale(std::max(1.0, *mid / CHI2_6DOF_MEDIAN));
    m_stats.drift_scale = m_drift->scale();
}

void LoopCloser::registerCandidates(
    std::size_t j, const emslam::egomotion::EgomotionEstimator& estimator)
{
    const std::vector<mrpt::poses::CPose3D>& x = m_graph.nodes();
    const Vec3 pj = positionOf(x[j]);
    const std::vector<std::size_t> order = candidateOrder(j, nearCandidates(j));
    const auto cur = m_keyframes[j].description;
    std::size_t gated = 0;
    for (const std::size_t i : order)
    {
        if (gated >= CONSENSUS_MIN)
        {
            break;  // enough for a consensus of this keyframe alone: the rest would cost, not add
        }
        const auto r = estimator.estimate(descriptionOf(i), cur);
        ++m_stats.registrations;
        if (!r.ok)
        {
            continue;
        }
        auto reg = std::make_unique<Registration>();
        reg->i = i;
        reg->j = j;
        reg->z = r.T_prev_cur;
        // A registration is one more egomotion step: without a curvature of
        // its own (e.g. a perfect fit), it gets the keyframe's.
        reg->covariance = r.has_covariance ? r.covariance : m_keyframes[j].covariance;
        reg->matches = r.final_matches;
        // Within three standard deviations of the chain, as it is now.
        const auto delta = emslam::rectify::actionDifference(x[j] - x[i], reg->z);
        const double dt2 = squaredNorm3(delta, 0);
        const double dr2 = squaredNorm3(delta, 3);
        const double var_t =
            m_drift->translationVariance(i, j, pj) + translationTrace(reg->covariance);
        const double var_r = m_drift->rotationVariance(i, j) + rotationTrace(reg->covariance);
        if (dt2 > GATE_SIGMAS * GATE_SIGMAS * var_t || dr2 > GATE_SIGMAS * GATE_SIGMAS * var_r)
        {
            continue;
        }
        ++m_stats.registered;
        ++gated;
        m_pool.push_back(std::move(reg));
    }
}

std::vector<std::pair<double, std::size_t>> LoopCloser::nearCandidates(std::size_t j)
{
    const std::vector<mrpt::poses::CPose3D>& x = m_graph.nodes();
    const Vec3 pj = positionOf(x[j]);
    const Vec3 vj = viewingDirection(x[j]);
    // The viewing directions may differ by the chain's rotation drift too.
    const auto viewsOverlap = [&](std::size_t i)
    {
        const double angle = std::min(
            M_PI, mrpt::DEG2RAD(m_p.max_angle_deg) +
                      GATE_SIGMAS * std::sqrt(m_drift->rotationVariance(i, j)));
        return viewingDirection(x[i]).dot(vj) >= std::cos(angle);
    };
    // The ball that holds every candidate: the drift from the first keyframe
    // bounds the drift from any (shortened by the loops closed).
    const double reach =
        m_p.max_distance + GATE_SIGMAS * std::sqrt(m_drift->translationVariance(0, j, pj));
    std::vector<std::pair<double, std::size_t>> near;
    m_grid->near(
        pj, reach,
        [&](std::size_t i)
        {
            if (i >= j || m_path[j] - m_path[i] < m_p.min_path_length ||
                (!m_keyframes[i].description && m_keyframes[i].kept.features.empty()) ||
                !viewsOverlap(i))
            {
                return;
            }
            const double d = (positionOf(x[i]) - pj).norm();
            if (d > reach)
            {
                return;
            }
            const double sigma = std::sqrt(m_drift->translationVariance(i, j, pj));
            if (d <= m_p.max_distance + GATE_SIGMAS * sigma)
            {
                near.emplace_back(d, i);
            }
        });
    m_stats.candidates += near.size();
    std::sort(near.begin(), near.end());
    near.resize(std::min(near.size(), static_cast<std::size_t>(m_p.max_candidates)));
    return near;
}

std::vector<std::size_t> LoopCloser::candidateOrder(
    std::size_t j, const std::vector<std::pair<double, std::size_t>>& near)
{
    // The keyframes that look most like j go first: they are there whatever
    // the drift, when the nearest by the estimate may not be the place.
    std::vector<std::size_t> order;
    if (m_p.place_candidates > 0)
    {
        const auto t_words = std::chrono::steady_clock::now();
        m_place_words = m_places.wordsOf(
            m_p.kept_features > 0 ? m_keyframes[j].kept
                                  : emslam::egomotion::EgomotionEstimator::compact(
                                        m_keyframes[j].description, PLACE_FEATURES));
        m_stats.place_ms +=
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_words)
                .count();
    }
    // While a loop is being followed (loop edges accepted in the window),
    // the drift is short again and the nearest are the place: registrations
    // by look would only cost.
    if (m_p.place_candidates > 0 && m_accepted.empty())
    {
        const double farthest = m_path[j] - m_p.min_path_length;
        const auto before = static_cast<std::size_t>(
            std::upper_bound(m_path.begin(), m_path.begin() + static_cast<long>(j), farthest) -
            m_path.begin());
        const auto t0 = std::chrono::steady_clock::now();
        for (const auto& m :
             m_places.query(m_place_words, before, static_cast<std::size_t>(m_p.place_candidates)))
        {
            order.push_back(m.place);
        }
        m_stats.place_ms +=
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        m_stats.place_visited_max = std::max(m_stats.place_visited_max, m_places.lastVisited());
        m_stats.place_candidates += order.size();
    }
    for (const auto& [d, i] : near)
    {
        if (std::find(order.begin(), order.end(), i) == order.end())
        {
            order.push_back(i);
        }
    }
    return order;
}

std::vector<std::unique_ptr<LoopCloser::Registration>> LoopCloser::takeConsensusGroup(
    std::size_t j, bool last_call)
{
    const std::size_t window = static_cast<std::size_t>(m_p.consensus_window);
    const auto expired = [&](const std::unique_ptr<Registration>& r) { return r->j + window <= j; };
    m_accepted.erase(
        std::remove_if(m_accepted.begin(), m_accepted.end(), expired), m_accepted.end());
    if (m_pool.empty())
    {
        return {};
    }
    for (auto& r : m_pool)
    {
        measure(*r);
    }
    for (auto& r : m_accepted)
    {
        measure(*r);
    }
    // Decided on and still alone: out (after the decision below).
    const auto drop = [&]
    {
        m_pool.erase(
            std::remove_if(
                m_pool.begin(), m_pool.end(),
                [&](const std::unique_ptr<Registration>& r)
                { return expired(r) && readyToDecide(*r, j); }),
            m_pool.end());
    };
    if (m_accepted.empty() && !last_call)
    {
        // A new loop (none accepted nearby) waits for its oldest registration.
        const auto oldest = std::min_element(
            m_pool.begin(), m_pool.end(), [](const auto& a, const auto& b) { return a->j < b->j; });
        if (!readyToDecide(**oldest, j))
        {
            return {};
        }
    }
    std::sort(
        m_pool.begin(), m_pool.end(),
        [](const auto& a, const auto& b) { return a->normalized < b->normalized; });
    const std::vector<std::size_t> best_group = bestConsensusGroup();
    // A new loop waits for its own group's oldest registration too: the
    // wait above may have been ended by an older look-alike, while the
    // revisit, just begun, has only a few members yet.
    if (!best_group.empty() && m_accepted.empty() && !last_call)
    {
        std::size_t oldest = best_group.front();
        for (std::size_t n : best_group)
        {
            oldest = m_pool[n]->j < m_pool[oldest]->j ? n : oldest;
        }
        if (!readyToDecide(*m_pool[oldest], j))
        {
            return {};
        }
    }
    std::vector<std::unique_ptr<Registration>> taken;
    if (!best_group.empty())
    {
        std::vector<std::unique_ptr<Registration>> rest;
        std::size_t g = 0;
        for (std::size_t n = 0; n < m_pool.size(); ++n)
        {
            if (g < best_group.size() && best_group[g] == n)
            {
                ++g;
                taken.push_back(std::move(m_pool[n]));
            }
            else
            {
                rest.push_back(std::move(m_pool[n]));
            }
        }
        m_pool = std::move(rest);
    }
    drop();
    return taken;
}

void LoopCloser::measure(Registration& r) const
{
    const std::vector<mrpt::poses::CPose3D>& x = m_graph.nodes();
    const Vec3 pj = positionOf(x[r.j]);
    const auto delta = emslam::rectify::actionDifference(x[r.j] - x[r.i], r.z);
    const double dt2 = squaredNorm3(delta, 0);
    const double dr2 = squaredNorm3(delta, 3);
    const double var_t =
        m_drift->translationVariance(r.i, r.j, pj) + translationTrace(r.covariance);
    const double var_r = m_drift->rotationVariance(r.i, r.j) + rotationTrace(r.covariance);
    r.normalized = dt2 / var_t + dr2 / var_r;
    r.correction = positionOf(x[r.i] + r.z) - pj;
}

bool LoopCloser::readyToDecide(const Registration& r, std::size_t j) const
{
    // A registration asking for a correction c could be a look-alike of a
    // place truly revisited anywhere within c (plus max_distance) further
    // on: it is decided on, and leaves the pool, only once the path went
    // that far past it and the window is over, so that a look-alike seen
    // first (a repeated corridor ahead of the real revisit) competes with
    // the revisit, whose correction is the smaller, as it would in a batch.
    return m_path[j] - m_path[r.j] >= r.correction.norm() + m_p.max_distance;
}

std::vector<std::size_t> LoopCloser::bestConsensusGroup() const
{
    // The group (the registrations agreeing with one, waiting or accepted
    // in the window) most likely to be the place revisited: the drift makes
    // a correction of normalised size n as likely as exp(-n/2), and each
    // registration that found the same correction on its own is evidence
    // for it: the largest support x exp(-n/2) wins. With a drift of metres a
    // look-alike may ask for a slightly smaller correction than the revisit,
    // which goes on agreeing with itself keyframe after keyframe; a
    // repeated corridor seen long before the revisit has the support, but
    // asks for a correction the drift makes far less likely.
    std::vector<std::size_t> best_group;
    double best_score = 0;
    for (const auto& seed : m_pool)
    {
        std::vector<std::size_t> group;
        for (std::size_t n = 0; n < m_pool.size(); ++n)
        {
            if (correctionsAgree(*seed, *m_pool[n]))
            {
                group.push_back(n);
            }
        }
        const auto votes = static_cast<std::size_t>(std::count_if(
            m_accepted.begin(), m_accepted.end(),
            [&](const auto& r) { return correctionsAgree(*seed, *r); }));
        const std::size_t support = group.size() + votes;
        const double score = std::log(static_cast<double>(support)) - 0.5 * seed->normalized;
        if (support >= CONSENSUS_MIN && (best_group.empty() || score > best_score))
        {
            best_score = score;
            best_group = std::move(group);
        }
    }
    return best_group;
}

bool LoopCloser::correctionsAgree(const Registration& a, const Registration& b) const
{
    const std::vector<mrpt::poses::CPose3D>& x = m_graph.nodes();
    const Vec3 at_j = positionOf(x[std::max(a.j, b.j)]);
    const Vec3 at_i = positionOf(x[std::max(a.i, b.i)]);
    const double var = m_drift->translationVariance(a.j, b.j, at_j) +
                       m_drift->translationVariance(a.i, b.i, at_i) +
                       translationTrace(a.covariance) + translationTrace(b.covariance);
    return (a.correction - b.correction).squaredNorm() <= GATE_SIGMAS * GATE_SIGMAS * var;
}

bool LoopCloser::continuesAcceptedLoop(
    const std::vector<std::unique_ptr<Registration>>& group) const
{
    // Each member agrees with the majority of the loop edges accepted in the
    // window: the same correction, so the same loop, whose registrations the
    // solved graph cannot all satisfy within their stated noise. A look-alike
    // asks for another correction than the loop being followed.
    if (m_accepted.empty())
    {
        return false;
    }
    return std::all_of(
        group.begin(), group.end(),
        [&](const auto& r)
        {
            const auto agreeing = std::count_if(
                m_accepted.begin(), m_accepted.end(),
                [&](const auto& a) { return correctionsAgree(*r, *a); });
            return 2 * static_cast<std::size_t>(agreeing) > m_accepted.size();
        });
}

double LoopCloser::loopEdgeGate() const
{
    // Every edge's covariance comes from the egomotion, whose errors are
    // its variances times the drift scale (the local registrations' median
    // misclosure): a loop edge's cost is tested against the χ² gate of the
    // covariances as the data show them. Real images (KITTI: 1.5) make
    // registrations of one true loop disagree beyond their stated noise.
    return GATE_CHI2_6DOF * m_drift->scale();
}

bool LoopCloser::tryAccept(std::vector<std::unique_ptr<Registration>> group)
{
    if (!m_stats.unreliable.empty())
    {
        return false;  // look-alikes: no loop closes any more
    }
    const double gate = loopEdgeGate();
    const std::size_t first_tag = EDGE_LOOP + m_edges.size();
    addGroupEdges(group, first_tag);
    bool disagrees = false;
    for (const auto& e : m_graph.edges())
    {
        disagrees = disagrees || (e.tag >= first_tag && 2 * m_graph.edgeCost(e) > gate);
    }
    if (disagrees)
    {
        // The solved graph must agree with the group and still with the loop
        // edges accepted nearby; a local solve that cannot is tried again
        // with every keyframe free (the correction may need the whole loop),
        // and if that cannot either, the group is a look-alike that got
        // through: out, and the graph back where it was.
        std::vector<std::pair<std::size_t, double>> offenders;
        const std::size_t first_free = firstFreeKeyframe(group);
        bool consistent = solveConsistently(first_free, first_tag, gate, offenders) ||
                          (first_free != 1 && solveConsistently(1, first_tag, gate, offenders));
        consistent = consistent || dropDisagreeingMembers(group, first_tag, gate, offenders);
        if (!consistent)
        {
            return refuseGroup(group, first_tag);
        }
    }
    recordLatency(group.front()->j);
    if (m_accepted.empty())
    {
        recordNewLoop(group);
    }
    acceptGroup(group);
    return disagrees;
}

void LoopCloser::addGroupEdges(
    std::vector<std::unique_ptr<Registration>>& group, std::size_t first_tag)
{
    for (std::size_t n = 0; n < group.size(); ++n)
    {
        Registration& r = *group[n];
        // What the graph still disagrees with the edge, before it is solved.
        r.misclosure =
            emslam::rectify::actionDifference(m_graph.node(r.j) - m_graph.node(r.i), r.z);
        r.tag = first_tag + n;
        m_graph.addEdge(r.i, r.j, r.z, r.covariance, r.tag);
    }
}

std::size_t LoopCloser::firstFreeKeyframe(
    const std::vector<std::unique_ptr<Registration>>& group) const
{
    // With loop edges accepted in the window, the map behind them is
    // consistent: only the keyframes since the oldest of them drifted,
    // and a local solve moves them (its cost follows the window, not the
    // run). Otherwise a new loop closes: every keyframe may move.
    if (m_accepted.empty())
    {
        return 1;
    }
    std::size_t first_free = group.front()->j;
    for (const auto& r : m_accepted)
    {
        first_free = std::min(first_free, r->j);
    }
    for (const auto& r : group)
    {
        first_free = std::min(first_free, r->j);
    }
    return first_free;
}

void LoopCloser::leaveUnconverged(
    const emslam::rectify::PoseGraph::Result& solved, int max_iterations, std::size_t first_free)
{
    // Stopped by its cap or cut short, not by the tolerance: the next solve starts from
    // these keyframes too, whatever it would have freed.
    if (solved.iterations >= max_iterations || solved.stopped)
    {
        m_unsolved_from = std::min(m_unsolved_from, std::max<std::size_t>(first_free, 1));
    }
}

bool LoopCloser::solveConsistently(
    std::size_t free_from,
    std::size_t first_tag,
    double gate,
    std::vector<std::pair<std::size_t, double>>& offenders)
{
    std::vector<std::size_t> check;
    for (const auto& r : m_accepted)
    {
        check.push_back(r->tag);
    }
    offenders.clear();
    const std::vector<mrpt::poses::CPose3D> before(
        m_graph.nodes().begin() + static_cast<long>(free_from), m_graph.nodes().end());
    const auto frame_before = m_graph.directionFrame();
    // A new loop bends every keyframe, by as much as the drift: it is solved
    // until it converges (outdoor eight, seed 3: 8 iterations left a 2.25 m
    // misclosure spread 0.84 m off the truth mid-run, where the polish, which
    // frees only what the last rectification changed, never reached).
    const int iterations = free_from <= 1 ? POLISH_ITERATIONS : ONLINE_ITERATIONS;
    const auto solved = m_graph.optimize(iterations, free_from, SOLVE_TOLERANCE);
    m_stats.local_solves += free_from > 1 ? 1 : 0;
    m_solved_upto = m_keyframes.size();
    if (m_stats.rounds == 0)
    {
        m_stats.initial_cost = solved.initial_cost;
    }
    m_stats.final_cost = solved.final_cost;
    ++m_stats.rounds;
    for (const auto& e : m_graph.edges())
    {
        const double cost = m_graph.edgeCost(e);
        const bool mine =
            e.tag >= first_tag ||
            (e.tag >= EDGE_LOOP && std::find(check.begin(), check.end(), e.tag) != check.end());
        if (mine && 2 * cost > gate)
        {
            offenders.emplace_back(e.tag, cost);
        }
    }
    if (offenders.empty())
    {
        leaveUnconverged(solved, iterations, free_from);
        return true;
    }
    for (std::size_t k = 0; k < before.size(); ++k)
    {
        m_graph.setNode(free_from + k, before[k]);
    }
    m_graph.setDirectionFrame(frame_before);
    return false;
}

bool LoopCloser::dropDisagreeingMembers(
    std::vector<std::unique_ptr<Registration>>& group,
    std::size_t first_tag,
    double gate,
    std::vector<std::pair<std::size_t, double>>& offenders)
{
    // A look-alike that agreed with the group closely enough to join it
    // (with a drift of metres, agreeing is loose) cannot be satisfied by
    // the solved graph while the rest are: the member it disagrees with
    // most is taken out and the rest solved again, while the rest are
    // still the majority of the group and a consensus.
    const std::size_t majority = group.size() / 2 + 1;
    while (!offenders.empty() && group.size() > std::max(majority, CONSENSUS_MIN))
    {
        const auto worst = std::max_element(
            offenders.begin(), offenders.end(),
            [](const auto& a, const auto& b) { return a.second < b.second; });
        if (worst->first < first_tag)
        {
            return false;  // a loop edge accepted before disagrees: the group is wrong
        }
        const std::size_t out = worst->first - first_tag;
        group.erase(group.begin() + static_cast<long>(out));
        m_graph.removeEdgesIf([&](const emslam::rectify::PoseGraph::Edge& e)
                              { return e.tag >= first_tag; });
        for (std::size_t n = 0; n < group.size(); ++n)
        {
            group[n]->tag = first_tag + n;
            m_graph.addEdge(
                group[n]->i, group[n]->j, group[n]->z, group[n]->covariance, group[n]->tag);
        }
        if (solveConsistently(1, first_tag, gate, offenders))
        {
            return true;
        }
    }
    return false;
}

bool LoopCloser::refuseGroup(
    const std::vector<std::unique_ptr<Registration>>& group, std::size_t first_tag)
{
    m_graph.removeEdgesIf([&](const emslam::rectify::PoseGraph::Edge& e)
                          { return e.tag >= first_tag; });
    m_stats.refused_groups += 1;
    m_stats.refused_edges += group.size();
    if (continuesAcceptedLoop(group))
    {
        return false;  // the loop followed, beyond its noise: no contradiction
    }
    m_stats.contradicting_groups += 1;
    m_stats.contradicting_edges += group.size();
    // A look-alike place fools the consensus once per window of
    // keyframes passing it: a group agreeing over several windows
    // counts as as many.
    std::set<std::size_t> keyframes;
    for (const auto& r : group)
    {
        keyframes.insert(r->j);
    }
    m_stats.contradicting_keyframes += keyframes.size();
    const auto window = static_cast<std::size_t>(m_p.consensus_window);
    m_contradicting_windows += (keyframes.size() + window - 1) / window;
    return checkContradictions();
}

namespace
{
/** Adds `value` as the (n+1)-th sample to a running mean and maximum. */
void addSample(double value, std::size_t n, double& mean, double& max)
{
    mean = (mean * static_cast<double>(n) + value) / static_cast<double>(n + 1);
    max = std::max(max, value);
}
}  // namespace

double LoopCloser::msSinceAdded(std::size_t k) const
{
    return std::chrono::duration<double, std::milli>(
               std::chrono::steady_clock::now() - m_keyframes[k].added)
        .count();
}

void LoopCloser::recordLatency(std::size_t j)
{
    addSample(
        msSinceAdded(j), m_stats.latency_count++, m_stats.latency_ms_mean, m_stats.latency_ms_max);
}

void LoopCloser::recordNewLoop(const std::vector<std::unique_ptr<Registration>>& group)
{
    const std::size_t first =
        (*std::min_element(
             group.begin(), group.end(), [](const auto& a, const auto& b) { return a->j < b->j; }))
            ->j;
    const std::size_t n = m_stats.new_loops++;
    addSample(
        msSinceAdded(first), n, m_stats.new_loop_latency_ms_mean, m_stats.new_loop_latency_ms_max);
    addSample(
        m_path.back() - m_path[first], n, m_stats.new_loop_wait_m_mean,
        m_stats.new_loop_wait_m_max);
}

void LoopCloser::acceptGroup(std::vector<std::unique_ptr<Registration>>& group)
{
    for (auto& reg : group)
    {
        const Registration& r = *reg;
        // A shortcut of the drift, as uncertain as the edge plus the
        // misclosure it had to absorb: the egomotion drifted that much
        // beyond what its covariance said (KITTI: corrections 3-4 sigma of
        // it), and may again on the way from here.
        m_drift->addShortcut(
            r.i, r.j, translationTrace(r.covariance) + squaredNorm3(r.misclosure, 0),
            rotationTrace(r.covariance) + squaredNorm3(r.misclosure, 3));
        m_dropped.push_back(false);
        m_edges.push_back(
            {m_keyframes[r.i].frame_index, m_keyframes[r.j].frame_index, r.z, r.matches});
        ++m_stats.loop_edges;
        m_accepted.push_back(std::move(reg));
    }
}

void LoopCloser::solve(int max_iterations, std::size_t first_free)
{
    first_free = std::min(first_free, m_unsolved_from);
    m_unsolved_from = NONE_UNSOLVED;
    m_solved_upto = m_keyframes.size();
    const double gate = loopEdgeGate();
    for (int pass = 0; pass < MAX_DROP_PASSES; ++pass)
    {
        const auto solved =
            m_graph.optimize(max_iterations, first_free, SOLVE_TOLERANCE, POLISH_MIN_DECREASE);
        leaveUnconverged(solved, max_iterations, first_free);
        if (m_stats.rounds == 0)
        {
            m_stats.initial_cost = solved.initial_cost;
        }
        m_stats.final_cost = solved.final_cost;
        ++m_stats.rounds;
        // A loop edge the solved graph still disagrees with beyond the bulk
        // of its own noise is a look-alike that got through: out.
        const std::size_t dropped = m_graph.removeEdgesIf(
            [&](const emslam::rectify::PoseGraph::Edge& e)
            {
                const bool drop = e.tag >= EDGE_LOOP && 2 * m_graph.edgeCost(e) > gate;
                if (drop)
                {
                    m_dropped[e.tag - EDGE_LOOP] = true;
                }
                return drop;
            });
        if (dropped == 0)
        {
            return;
        }
        m_stats.dropped_edges += dropped;
        m_accepted.erase(
            std::remove_if(
                m_accepted.begin(), m_accepted.end(),
                [&](const auto& r) { return m_dropped[r->tag - EDGE_LOOP]; }),
            m_accepted.end());
        if (checkContradictions())
        {
            return;
        }
    }
}

bool LoopCloser::checkContradictions()
{
    if (!m_stats.unreliable.empty())
    {
        return false;
    }
    // Contradictions: each loop edge dropped and each group refused while
    // asking for another correction than the loop followed (its edges fail
    // together), as many times as it spans consensus windows of keyframes.
    // A true loop edge fails a χ² test by chance; a single look-alike place,
    // passed on the way in and out, may fool the consensus twice; more than
    // both is a world of look-alikes. Every loop edge accepted (dropped
    // later or not) and every refused group's edge was tested against a
    // solved graph at least once.
    const std::size_t contradictions = m_stats.dropped_edges + m_contradicting_windows;
    const std::size_t tested = m_stats.loop_edges + m_stats.refused_edges;
    const std::size_t chance = std::max<std::size_t>(
        LOOK_ALIKE_FOOLS, poissonBulk(GATE_FALSE_ALARM * static_cast<double>(tested)));
    if (contradictions <= chance)
    {
        return false;
    }
    m_stats.unreliable =
        "the solved pose graph contradicted the registrations " + std::to_string(contradictions) +
        " times (" + std::to_string(m_stats.dropped_edges) + " of " + std::to_string(tested) +
        " loop edges dropped, " + std::to_string(m_stats.contradicting_keyframes) +
        " keyframes in " + std::to_string(m_stats.contradicting_groups) +
        " refused groups asking for another correction; chance and one look-alike place explain " +
        std::to_string(chance) + "): look-alike places, loop edges withdrawn";
    // The loop edges kept so far are as suspect: out, and the graph back to
    // what the egomotion (and the local edges) say.
    const std::size_t withdrawn = m_graph.removeEdgesIf(
        [&](const emslam::rectify::PoseGraph::Edge& e)
        {
            if (e.tag < EDGE_LOOP)
            {
                return false;
            }
            m_dropped[e.tag - EDGE_LOOP] = true;
            return true;
        });
    m_stats.withdrawn_edges += withdrawn;
    m_accepted.clear();
    // From the chain, not from where the false loops bent the graph: after
    // a drift of metres a few iterations from there stay bent (paper-regime
    // Chancellor loop, seed 3: SLAM ATE 19.9 m against the egomotion's 7.7).
    placeAlongOdometry();
    const auto solved = m_graph.optimize(POLISH_ITERATIONS, 1, SOLVE_TOLERANCE);
    m_stats.final_cost = solved.final_cost;
    ++m_stats.rounds;
    std::lock_guard<std::mutex> lock(m_out_mutex);
    m_published_unreliable = m_stats.unreliable;
    return true;
}

void LoopCloser::placeAlongOdometry()
{
    // Odometry edges join consecutive keyframes, in the order added; a
    // saved map held fixed stays.
    for (const auto& e : m_graph.edges())
    {
        if (e.tag == EDGE_ODOMETRY && e.to >= m_graph.fixedPrefix())
        {
            m_graph.setNode(e.to, m_graph.node(e.from) + e.measurement);
        }
    }
}

std::string LoopCloser::unreliable() const
{
    std::lock_guard<std::mutex> lock(m_out_mutex);
    return m_published_unreliable;
}

void LoopCloser::publishPoses(bool all)
{
    const std::vector<mrpt::poses::CPose3D>& x = m_graph.nodes();
    std::lock_guard<std::mutex> lock(m_out_mutex);
    if (all)
    {
        m_published.clear();
    }
    for (std::size_t k = m_published.size(); k < x.size(); ++k)
    {
        m_published.push_back({m_keyframes[k].frame_index, x[k]});
    }
    m_published_loops.clear();
    for (std::size_t e = 0; e < m_edges.size(); ++e)
    {
        if (!m_dropped[e])
        {
            m_published_loops.emplace_back(m_edges[e].frame_from, m_edges[e].frame_to);
        }
    }
}

std::optional<LoopCloser::KeyframePose> LoopCloser::lastPose() const
{
    std::lock_guard<std::mutex> lock(m_out_mutex);
    if (m_published.empty())
    {
        return std::nullopt;
    }
    return m_published.back();
}

std::vector<LoopCloser::KeyframePose> LoopCloser::currentPoses() const
{
    std::lock_guard<std::mutex> lock(m_out_mutex);
    return m_published;
}

std::vector<std::pair<std::size_t, std::size_t>> LoopCloser::currentLoops() const
{
    std::lock_guard<std::mutex> lock(m_out_mutex);
    return m_published_loops;
}

std::vector<mrpt::poses::CPose3D> LoopCloser::close(
    const std::vector<mrpt::poses::CPose3D>& poses,
    const emslam::egomotion::EgomotionEstimator& estimator,
    const std::function<bool()>& stop)
{
    const auto t0 = std::chrono::steady_clock::now();
    const auto stopped = [&] { return stop && stop(); };
    {
        std::lock_guard<std::mutex> lock(m_in_mutex);
        if (poses.size() != m_added)
        {
            throw std::invalid_argument(
                "LoopCloser::close: " + std::to_string(poses.size()) + " poses for " +
                std::to_string(m_added) + " keyframes");
        }
    }
    for (Keyframe& k : takeIncoming())
    {
        const std::size_t j = m_keyframes.size();
        const mrpt::poses::CPose3D T = k.motion ? *k.motion
                                       : j == 0 ? mrpt::poses::CPose3D()
                                                : poses[j] - poses[j - 1];
        integrate(std::move(k), T, estimator, !stopped());
    }
    const std::size_t n = m_keyframes.size();
    if (n < 2)
    {
        return poses;
    }
    if (!stopped())
    {
        // A loop still waiting for its window to end is decided now.
        auto group = takeConsensusGroup(n - 1, true);
        if (!group.empty())
        {
            tryAccept(std::move(group));
        }
    }
    // The graph's world is its first keyframe; the given poses' may not be
    // (the rectifier moves a_0 for the Manhattan energies).
    const mrpt::poses::CPose3D origin = poses[0];
    for (std::size_t k = 0; k < n; ++k)
    {
        m_graph.setNode(k, origin + m_graph.node(k));
    }
    // The levelling's world up turns with the graph's world.
    const auto turned = [&origin](emslam::rectify::PoseGraph::DirectionFrame f)
    {
        const Vec3 w = origin.getRotationMatrix().asEigen() * Vec3(f.world.x, f.world.y, f.world.z);
        f.world = {w.x(), w.y(), w.z()};
        return f;
    };
    m_graph.setDirectionFrame(turned(m_graph.directionFrame()));
    m_levelled_for = turned(m_levelled_for);
    // A run found unreliable (look-alikes) keeps the graph its loop edges'
    // withdrawal left, unpolished: on the periodic floors (lookalike_periodic
    // seed 64) the polish's levelling drew the upper floor 1.4 m down, SLAM
    // ATE 1.02 m against the egomotion's 0.78 m (unpolished: 0.74 m).
    if (!stopped() && m_stats.unreliable.empty())
    {
        // The odometry edges take the rectified relative poses; the
        // keyframes before the first that moved need not.
        std::vector<KeyframePose> rectified;
        for (std::size_t k = 0; k < n; ++k)
        {
            rectified.push_back({m_keyframes[k].frame_index, poses[k]});
        }
        const std::size_t first_changed = applyRectified(rectified);
        // The levelling is online: the ups of the last keyframes join and
        // the polish's solve levels them with the rest.
        const auto t_level = std::chrono::steady_clock::now();
        relevel();
        const auto t_solve = std::chrono::steady_clock::now();
        solve(POLISH_ITERATIONS, std::min(first_changed, n - 1));
        const auto ms = [](auto a, auto b)
        { return std::chrono::duration<double, std::milli>(b - a).count(); };
        m_stats.polish_level_ms = ms(t_level, t_solve);
        m_stats.polish_solve_ms = ms(t_solve, std::chrono::steady_clock::now());
    }
    m_stats.loop_edges -= m_stats.dropped_edges + m_stats.withdrawn_edges;
    std::vector<LoopEdge> kept;
    for (std::size_t e = 0; e < m_edges.size(); ++e)
    {
        if (!m_dropped[e])
        {
            kept.push_back(m_edges[e]);
        }
    }
    m_edges = std::move(kept);
    m_dropped.assign(m_edges.size(), false);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    m_stats.polish_ms = ms;
    m_stats.ms += ms;
    publishPoses(true);
    return m_graph.nodes();
}

std::size_t LoopCloser::relevel()
{
    const std::size_t n = m_keyframes.size();
    if (!m_p.vertical_prior || n < 2)
    {
        return n;
    }
    // How far each keyframe may be tilted beyond the levelled ones: the
    // egomotion's rotation variance (per axis) along the chain since the
    // last keyframe a solve moved; none for those.
    std::vector<std::optional<emslam::stereo::VerticalMeasurement>> verticals(n);
    std::vector<double> tilt_variance(n, 0.0);
    for (std::size_t k = 0; k < n; ++k)
    {
        verticals[k] = m_keyframes[k].vertical;
        if (k >= m_solved_upto && k > 0)
        {
            tilt_variance[k] = tilt_variance[k - 1] + rotationTrace(m_keyframes[k].covariance) / 3;
        }
    }
    const LevelFloorsStats level = relevelFloors(
        m_graph, verticals, tilt_variance, m_levelled_for, std::min(m_ungated_from, m_gated_upto),
        mrpt::DEG2RAD(m_p.vertical_max_bias_deg));
    m_ungated_from = NONE_UNSOLVED;
    m_gated_upto = n;
    m_stats.verticals_measured = level.measured;
    m_stats.verticals_used = level.used;
    m_stats.vertical_drift_deg = level.drift_deg;
    m_stats.vertical_bias_deg = level.bias_deg;
    m_stats.vertical_correlation_time = level.correlation_time;
    if (level.first_changed <= 1)
    {
        // The next solve levels every keyframe for these.
        m_levelled_for = m_graph.directionFrame();
        ++m_stats.level_resolves;
    }
    m_unsolved_from = std::min(m_unsolved_from, level.first_changed);
    return level.first_changed;
}

LoopCloser::Snapshot LoopCloser::snapshot() const
{
    Snapshot s;
    const std::size_t n = m_keyframes.size();
    if (n == 0)
    {
        return s;
    }
    // In the graph's own world (after close() it is the rectifier's).
    const mrpt::poses::CPose3D origin = m_graph.node(0);
    for (std::size_t k = 0; k < n; ++k)
    {
        const Keyframe& kf = m_keyframes[k];
        Snapshot::Keyframe out;
        out.frame_index = kf.frame_index;
        out.kept = kf.kept.features.empty() && kf.description
                       ? emslam::egomotion::EgomotionEstimator::compact(
                             kf.description, static_cast<std::size_t>(m_p.kept_features))
                       : kf.kept;
        out.covariance = kf.covariance;
        out.motion = kf.motion;
        out.predicted = kf.predicted;
        out.vertical = kf.vertical;
        s.keyframes.push_back(std::move(out));
        s.nodes.push_back(m_graph.node(k) - origin);
    }
    // The loop edges renumbered in the order they are in the graph; their
    // match counts from the accepted list.
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> matches;
    for (const LoopEdge& e : m_edges)
    {
        matches[{e.frame_from, e.frame_to}] = e.matches;
    }
    s.loop_tag = EDGE_LOOP;
    for (emslam::rectify::PoseGraph::Edge e : m_graph.edges())
    {
        if (e.tag >= EDGE_LOOP)
        {
            LoopEdge l;
            l.frame_from = m_keyframes[e.from].frame_index;
            l.frame_to = m_keyframes[e.to].frame_index;
            l.measurement = e.measurement;
            const auto it = matches.find({l.frame_from, l.frame_to});
            l.matches = it != matches.end() ? it->second : 0;
            e.tag = EDGE_LOOP + s.loop_edges.size();
            s.loop_edges.push_back(l);
        }
        s.edges.push_back(e);
    }
    s.local_misclosures = m_local_misclosures;
    s.largest_step_t = m_largest_step_t;
    s.largest_step_r = m_largest_step_r;
    return s;
}

void LoopCloser::seed(const Snapshot& s, std::size_t frame_offset, bool hold_fixed)
{
    {
        std::lock_guard<std::mutex> lock(m_in_mutex);
        if (m_added > 0 || !m_keyframes.empty())
        {
            throw std::logic_error("LoopCloser::seed after addKeyframe()");
        }
    }
    const std::size_t n = s.keyframes.size();
    if (s.nodes.size() != n)
    {
        throw std::invalid_argument(
            "LoopCloser::seed: " + std::to_string(s.nodes.size()) + " poses for " +
            std::to_string(n) + " keyframes");
    }
    for (const auto& e : s.edges)
    {
        if (e.from >= n || e.to >= n || e.from == e.to ||
            (e.tag >= s.loop_tag && e.tag - s.loop_tag >= s.loop_edges.size()) ||
            (e.tag < s.loop_tag && e.tag > EDGE_LOCAL))
        {
            throw std::invalid_argument(
                "LoopCloser::seed: an edge joins keyframes " + std::to_string(e.from) + " and " +
                std::to_string(e.to) + " of " + std::to_string(n));
        }
    }
    for (std::size_t j = 0; j < n; ++j)
    {
        const Snapshot::Keyframe& in = s.keyframes[j];
        const mrpt::poses::CPose3D& pose = s.nodes[j];
        m_graph.addNode(pose);
        double unmeasured_t = 0, unmeasured_r = 0;
        if (in.predicted)
        {
            unmeasured_t = s.largest_step_t * s.largest_step_t;
            unmeasured_r = s.largest_step_r * s.largest_step_r;
        }
        const Vec3 previous = j == 0 ? Vec3::Zero() : positionOf(s.nodes[j - 1]);
        m_drift->append(previous, in.covariance, unmeasured_t, unmeasured_r);
        m_path.push_back(j == 0 ? 0.0 : m_path.back() + (positionOf(pose) - previous).norm());
        Keyframe k;
        k.frame_index = frame_offset + in.frame_index;
        k.kept = in.kept;
        k.covariance = in.covariance;
        k.motion = in.motion;
        k.predicted = in.predicted;
        k.vertical = in.vertical;
        k.added = std::chrono::steady_clock::now();
        m_keyframe_of_frame[k.frame_index] = j;
        if (m_p.place_candidates > 0)
        {
            m_places.add(j, m_places.wordsOf(k.kept));
        }
        m_stats.kept_bytes += k.kept.bytes();
        m_keyframes.push_back(std::move(k));
    }
    for (emslam::rectify::PoseGraph::Edge e : s.edges)
    {
        if (e.tag >= s.loop_tag)
        {
            e.tag = EDGE_LOOP + (e.tag - s.loop_tag);
        }
        m_graph.addEdge(e);
    }
    for (const LoopEdge& l : s.loop_edges)
    {
        LoopEdge e = l;
        e.frame_from += frame_offset;
        e.frame_to += frame_offset;
        m_edges.push_back(e);
        m_dropped.push_back(false);
    }
    m_stats.loop_edges += s.loop_edges.size();
    m_seeded = n;
    m_stats.place_index_bytes = m_places.bytes();
    m_local_misclosures = s.local_misclosures;
    if (m_local_misclosures.size() > MISCLOSURE_SAMPLES)
    {
        m_local_misclosures.resize(MISCLOSURE_SAMPLES);
    }
    m_local_misclosure_next = m_local_misclosures.size() % MISCLOSURE_SAMPLES;
    updateDriftScale();
    m_largest_step_t = s.largest_step_t;
    m_largest_step_r = s.largest_step_r;
    // Solved as saved; the ups they saw are gated again with the new ones.
    m_solved_upto = n;
    m_ungated_from = 0;
    if (hold_fixed)
    {
        m_graph.setFixedPrefix(n);
    }
    m_grid->rebuild(m_graph.nodes());
    {
        std::lock_guard<std::mutex> lock(m_in_mutex);
        m_added = n;
    }
    publishPoses(true);
}

}  // namespace emslam::slam
