// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/egomotion/FeatureMatcher.h>
#include <emslam/egomotion/LwoRefinement.h>
#include <emslam/egomotion/StereoReprojectionRefinement.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

namespace emslam::egomotion
{
namespace
{
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void require(bool ok, const std::string& key, const std::string& what)
{
    if (!ok)
    {
        throw std::invalid_argument("[EgomotionEstimator] " + key + ": " + what);
    }
}

bool finite(const mrpt::math::TPoint3Df& p)
{
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}
}  // namespace

/** A frame after stages 1-2a: its features (finite 3D points only) and their
 * descriptors, computed once per frame. */
struct EgomotionEstimator::Described
{
    FeatureList features;
    Descriptors descriptors;
    mrpt::img::TCamera camera;  //!< of the intensity image, for guided matching
    double baseline{0};         //!< stereo baseline [m]; 0 for a depth camera
    double ms_features{0}, ms_descriptors{0};
};

namespace
{
/** Every key of the section, once for load and save. */
void visit(EgomotionEstimator::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("window_size", p.window_size, "|W|, GLM non-maximum window [px]");
    v.field("min_gradient", p.min_gradient, "gradient magnitude floor for features");
    v.field("similarity_min", p.similarity_min, "S_min, in (0, 1]");
    v.field("lwo_sigma_min", p.lwo_sigma_min, "sigma_min of LWO");
    v.field("min_final_matches", p.min_final_matches, "fewer matches after LWO: the step failed");
    v.field("lp_num_rings", p.lp_num_rings, "log-polar descriptor rings");
    v.field("lp_num_angles", p.lp_num_angles, "log-polar descriptor angles");
    v.field("lp_radius", p.lp_radius, "log-polar window radius [px]");
    v.field("euclidean_init", p.euclidean_init, "closed-form start of the Dpp minimisation");
    v.field(
        "joint_refinement", p.joint_refinement,
        "Levenberg-Marquardt on all six parameters after the alternating CG");
    v.field(
        "reprojection_refinement", p.reprojection_refinement,
        "polish the pose by the stereo reprojection error (stereo only)");
    v.field("max_lwo_matches", p.max_lwo_matches, "most similar matches kept for LWO");
    v.field(
        "guided_matching", p.guided_matching,
        "match near the constant-velocity prediction first (full search if it fails)");
    v.field("guided_radius", p.guided_radius, "guided search radius, fraction of the image width");
    v.field(
        "experimental_covariance_lwo_truncation", p.experimental_covariance_lwo_truncation,
        "widen the pose covariance for the residuals LWO cut off");
    v.field(
        "experimental_match_distinctiveness", p.experimental_match_distinctiveness,
        "a match's runner-up elsewhere must be this times as far (Pearson distance); 1: off");
}
}  // namespace

void EgomotionEstimator::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void EgomotionEstimator::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void EgomotionEstimator::TParameters::validate() const
{
    // Upper bounds keep the descriptor and window sizes from overflowing
    // allocations before any frame is seen.
    require(
        window_size >= 3 && window_size <= 128, "window_size",
        "must be in [3, 128] (got " + std::to_string(window_size) + ")");
    require(
        std::isfinite(min_gradient) && min_gradient >= 0 && min_gradient <= 1e6, "min_gradient",
        "must be in [0, 1e6] (got " + std::to_string(min_gradient) + ")");
    require(
        similarity_min > 0 && similarity_min <= 1, "similarity_min",
        "must be in (0, 1] (got " + std::to_string(similarity_min) + ")");
    require(
        std::isfinite(lwo_sigma_min) && lwo_sigma_min > 0 && lwo_sigma_min <= 1e6, "lwo_sigma_min",
        "must be in (0, 1e6] (got " + std::to_string(lwo_sigma_min) + ")");
    require(
        min_final_matches >= 3 && min_final_matches <= 1000000, "min_final_matches",
        "must be in [3, 1000000] (a pose needs 3 points; got " + std::to_string(min_final_matches) +
            ")");
    require(
        lp_num_rings >= 2 && lp_num_rings <= 64, "lp_num_rings",
        "must be in [2, 64] (got " + std::to_string(lp_num_rings) + ")");
    require(
        lp_num_angles >= 4 && lp_num_angles <= 256, "lp_num_angles",
        "must be in [4, 256] (got " + std::to_string(lp_num_angles) + ")");
    require(
        std::isfinite(lp_radius) && lp_radius > 1 && lp_radius <= 256, "lp_radius",
        "must be in (1, 256] px (got " + std::to_string(lp_radius) + ")");
    require(
        max_lwo_matches >= min_final_matches && max_lwo_matches <= 1000000, "max_lwo_matches",
        "must be in [min_final_matches, 1000000] (got " + std::to_string(max_lwo_matches) +
            ", min_final_matches = " + std::to_string(min_final_matches) + ")");
    require(
        guided_radius > 0 && guided_radius <= 1, "guided_radius",
        "must be in (0, 1] of the image width (got " + std::to_string(guided_radius) + ")");
    require(
        experimental_match_distinctiveness >= 1 && experimental_match_distinctiveness <= 100,
        "experimental_match_distinctiveness",
        "must be in [1, 100] (1: off; got " + std::to_string(experimental_match_distinctiveness) +
            ")");
}

double lwoTruncationVarianceFactor(double q)
{
    if (!(q > 0.0 && q <= 1.0))
    {
        throw std::invalid_argument(
            "lwoTruncationVarianceFactor: the kept fraction must be in (0, 1] (got " +
            std::to_string(q) + ")");
    }
    if (q == 1.0)
    {
        return 1.0;
    }
    // c with erf(c / sqrt 2) = q, by bisection (erf is increasing).
    double lo = 0.0;
    double hi = 40.0;
    for (int k = 0; k < 200; ++k)
    {
        const double mid = 0.5 * (lo + hi);
        (std::erf(mid / std::sqrt(2.0)) < q ? lo : hi) = mid;
    }
    const double c = 0.5 * (lo + hi);
    const double pdf = std::exp(-0.5 * c * c) / std::sqrt(2.0 * M_PI);
    // Var(x | |x| < c) = 1 - 2 c φ(c) / q for a unit Gaussian.
    const double truncated = 1.0 - 2.0 * c * pdf / q;
    return truncated > 0.0 ? 1.0 / truncated : std::numeric_limits<double>::infinity();
}

EgomotionEstimator::EgomotionEstimator(const TParameters& p) : m_params(p)
{
    m_params.validate();
}

std::vector<emslam::stereo::PixelCoord> EgomotionEstimator::locateFeatures(
    const cv::Mat& intensity) const
{
    GlmFeatureExtractor::TParameters gp;
    gp.window_size = m_params.window_size;
    gp.min_gradient = static_cast<float>(m_params.min_gradient);
    return GlmFeatureExtractor(gp).locate(intensity, m_located);
}

EgomotionEstimator::Described EgomotionEstimator::describe(
    const emslam::stereo::StereoFrame& f) const
{
    Described d;
    d.camera = f.camera.leftCamera;
    d.baseline = emslam::stereo::baselineOf(f.camera);
    auto t0 = Clock::now();
    if (!f.intensity.empty() && f.intensity.type() == CV_8UC1 && !f.points.empty())
    {
        GlmFeatureExtractor::TParameters gp;
        gp.window_size = m_params.window_size;
        gp.min_gradient = static_cast<float>(m_params.min_gradient);
        d.features = GlmFeatureExtractor(gp).extract(f, m_located.get());
        // A NaN/inf point would poison LWO's sums and the pose energy.
        d.features.erase(
            std::remove_if(
                d.features.begin(), d.features.end(),
                [](const Feature& ft) { return !finite(ft.point); }),
            d.features.end());
    }
    m_located.reset();  // one frame's: never read for another
    d.ms_features = msSince(t0);
    t0 = Clock::now();
    if (!d.features.empty())
    {
        LogPolarDescriptorExtractor::TParameters lp;
        lp.num_rings = m_params.lp_num_rings;
        lp.num_angles = m_params.lp_num_angles;
        lp.radius = static_cast<float>(m_params.lp_radius);
        d.descriptors = LogPolarDescriptorExtractor(lp).compute(f.intensity, d.features);
    }
    d.ms_descriptors = msSince(t0);
    return d;
}

MatchList EgomotionEstimator::guidedMatches(
    const Described& prev,
    const Described& cur,
    const mrpt::poses::CPose3D& T_prev_cur,
    double radius_factor,
    bool distinct) const
{
    // Where each previous feature appears if the camera moves as predicted:
    // its point in the current frame (inverse action), projected.
    const mrpt::poses::CPose3D T_cur_prev = -T_prev_cur;
    const auto& K = cur.camera;
    std::vector<cv::Point2f> predicted(prev.features.size());
    for (std::size_t i = 0; i < prev.features.size(); ++i)
    {
        const auto& p = prev.features[i].point;
        double x = 0, y = 0, z = 0;
        T_cur_prev.composePoint(p.x, p.y, p.z, x, y, z);
        predicted[i] = z > 1e-3 ? cv::Point2f(
                                      static_cast<float>(K.fx() * x / z + K.cx()),
                                      static_cast<float>(K.fy() * y / z + K.cy()))
                                : cv::Point2f(NAN, NAN);
    }
    const auto radius =
        static_cast<float>(radius_factor * m_params.guided_radius * static_cast<double>(K.ncols));
    return matchMutualGuided(
        prev.descriptors, cur.descriptors, predicted, cur.features, radius,
        static_cast<float>(m_params.similarity_min),
        distinct ? distinctiveness(prev, cur) : Distinctiveness{});
}

Distinctiveness EgomotionEstimator::distinctiveness(
    const Described& prev, const Described& cur) const
{
    Distinctiveness d;
    d.ratio = static_cast<float>(m_params.experimental_match_distinctiveness);
    // A candidate within the descriptor window of the best describes much
    // of the same pixels: the best shifted, not a look-alike.
    d.same_place_px = static_cast<float>(m_params.lp_radius);
    d.prev_features = &prev.features;
    d.cur_features = &cur.features;
    return d;
}

EgomotionResult EgomotionEstimator::estimateDescribed(
    const Described& prev,
    const Described& cur,
    const mrpt::poses::CPose3D* prediction,
    bool fall_back_to_paper) const
{
    const bool distinct = m_params.experimental_match_distinctiveness > 1;
    EgomotionResult r = estimateMatching(prev, cur, prediction, distinct);
    if (!r.ok && distinct && fall_back_to_paper)
    {
        // Too few distinct matches (a view of one periodic wall): the
        // paper's matching, whose look-alikes LWO must sort out, rather than
        // a lost step.
        EgomotionResult paper = estimateMatching(prev, cur, prediction, false);
        paper.distinct_fallback = true;
        paper.ms_matching += r.ms_matching;
        paper.ms_lwo += r.ms_lwo;
        paper.ms_pose += r.ms_pose;
        paper.ms_total += r.ms_total - r.ms_features - r.ms_descriptors;
        return paper;
    }
    return r;
}

EgomotionResult EgomotionEstimator::estimateMatching(
    const Described& prev,
    const Described& cur,
    const mrpt::poses::CPose3D* prediction,
    bool distinct) const
{
    const auto fullSearch = [&]
    {
        return estimateWithMatches(
            prev, cur,
            [&]
            {
                return matchMutual(
                    prev.descriptors, cur.descriptors, static_cast<float>(m_params.similarity_min),
                    distinct ? distinctiveness(prev, cur) : Distinctiveness{});
            });
    };
    // The attempt `spent` was made before `r` on the same frames: charge its time to r.
    const auto chargeEarlierAttempt = [](EgomotionResult& r, const EgomotionResult& spent)
    {
        r.ms_matching += spent.ms_matching;
        r.ms_lwo += spent.ms_lwo;
        r.ms_pose += spent.ms_pose;
        r.ms_total += spent.ms_total - spent.ms_features - spent.ms_descriptors;
    };
    if (prediction == nullptr || !m_params.guided_matching || cur.camera.ncols == 0)
    {
        return fullSearch();
    }
    // The first pass only predicts where to match again: its motion comes
    // from the closed-form fit of its LWO inliers, not the Dpp minimisation.
    const auto firstPass = [&](PoseStage stage)
    {
        return estimateWithMatches(
            prev, cur, [&] { return guidedMatches(prev, cur, *prediction, 1.0, distinct); }, stage);
    };
    EgomotionResult guided = firstPass(PoseStage::ClosedFormOnly);
    guided.guided = true;
    if (guided.ok)
    {
        // Match again around the motion just found, in a quarter of the
        // window: features whose true match lay outside the window of a wrong
        // prediction now get it, and far look-alikes drop out.
        EgomotionResult again = estimateWithMatches(
            prev, cur, [&] { return guidedMatches(prev, cur, guided.T_prev_cur, 0.25, distinct); },
            PoseStage::Dpp);
        if (!again.ok)
        {
            // Rare: the first pass's matches, with the Dpp pose after all.
            EgomotionResult first = firstPass(PoseStage::Dpp);
            first.guided = true;
            chargeEarlierAttempt(first, guided);
            chargeEarlierAttempt(first, again);
            return first;
        }
        again.guided = true;
        chargeEarlierAttempt(again, guided);
        return again;
    }
    // The motion was not the predicted one (a stop, a turn): search everywhere.
    EgomotionResult full = fullSearch();
    full.guided_fallback = true;
    chargeEarlierAttempt(full, guided);
    return full;
}

EgomotionResult EgomotionEstimator::estimateWithMatches(
    const Described& prev,
    const Described& cur,
    const std::function<MatchList()>& match,
    PoseStage stage) const
{
    const auto t_start = Clock::now();
    EgomotionResult r;
    r.features_prev = prev.features.size();
    r.features_cur = cur.features.size();
    r.ms_features = cur.ms_features;
    r.ms_descriptors = cur.ms_descriptors;
    auto fail = [&](const std::string& why)
    {
        r.ok = false;
        r.T_prev_cur = mrpt::poses::CPose3D();
        r.failure_reason = why + " (features " + std::to_string(r.features_prev) + "/" +
                           std::to_string(r.features_cur) + ", matches " +
                           std::to_string(r.initial_matches) + " -> " +
                           std::to_string(r.final_matches) + " after LWO)";
        r.ms_total = r.ms_features + r.ms_descriptors + msSince(t_start);
        return r;
    };
    const auto min_final = static_cast<std::size_t>(m_params.min_final_matches);
    if (prev.features.size() < min_final || cur.features.size() < min_final ||
        prev.descriptors.dim != cur.descriptors.dim)
    {
        return fail("too few features");
    }

    auto t0 = Clock::now();
    MatchList matches = match();
    const auto max_m = static_cast<std::size_t>(m_params.max_lwo_matches);
    if (matches.size() > max_m)
    {
        // LWO is O(M^2): keep the most similar matches.
        std::nth_element(
            matches.begin(), matches.begin() + static_cast<std::ptrdiff_t>(max_m), matches.end(),
            [](const Match& x, const Match& y) { return x.similarity > y.similarity; });
        matches.resize(max_m);
    }
    r.initial_matches = matches.size();
    r.ms_matching = msSince(t0);
    if (matches.size() < min_final)
    {
        return fail("too few matches");
    }

    t0 = Clock::now();
    std::vector<mrpt::math::TPoint3Df> a, b;
    a.reserve(matches.size());
    b.reserve(matches.size());
    for (const auto& m : matches)
    {
        a.push_back(prev.features.at(static_cast<std::size_t>(m.prev)).point);
        b.push_back(cur.features.at(static_cast<std::size_t>(m.cur)).point);
    }
    const LwoResult lwo = refineLwo(a, b, m_params.lwo_sigma_min);
    r.lwo_iterations = lwo.iterations;
    r.final_matches = lwo.kept.size();
    r.ms_lwo = msSince(t0);
    if (r.final_matches < min_final)
    {
        return fail("too few matches after LWO");
    }

    t0 = Clock::now();
    std::vector<mrpt::math::TPoint3Df> ka, kb;
    ka.reserve(lwo.kept.size());
    kb.reserve(lwo.kept.size());
    for (int i : lwo.kept)
    {
        ka.push_back(a[static_cast<std::size_t>(i)]);
        kb.push_back(b[static_cast<std::size_t>(i)]);
    }
    if (stage == PoseStage::ClosedFormOnly)
    {
        r.T_prev_cur = DppPoseEstimator::euclideanFit(ka, kb);
        r.ms_pose = msSince(t0);
        r.ok = true;
        r.ms_total = r.ms_features + r.ms_descriptors + msSince(t_start);
        return r;
    }
    DppPoseEstimator::TParameters pp;
    pp.euclidean_init = m_params.euclidean_init;
    pp.joint_refinement = m_params.joint_refinement;
    const auto pose = DppPoseEstimator(pp).estimate(ka, kb);
    r.T_prev_cur = pose.T_prev_cur;
    r.energy = pose.energy;
    r.covariance = pose.covariance;
    r.has_covariance = pose.has_covariance;
    if (m_params.reprojection_refinement && cur.baseline > 0)
    {
        const auto refined = StereoReprojectionRefinement::refine(
            ka, kb, pose.T_prev_cur, cur.baseline, cur.camera.fx());
        r.T_prev_cur = refined.T_prev_cur;
        r.energy = DppPoseEstimator::energy(ka, kb, r.T_prev_cur);
        // The uncertainty of the estimate that is used; if it has none (a
        // degenerate geometry), the Dpp's at the polished pose.
        r.has_covariance = refined.has_covariance;
        r.covariance = refined.covariance;
        if (!r.has_covariance)
        {
            r.has_covariance = DppPoseEstimator::covarianceAt(ka, kb, r.T_prev_cur, r.covariance);
        }
    }
    r.ms_pose = msSince(t0);
    if (r.has_covariance && m_params.experimental_covariance_lwo_truncation &&
        r.initial_matches > 0)
    {
        r.covariance *= lwoTruncationVarianceFactor(
            static_cast<double>(r.final_matches) / static_cast<double>(r.initial_matches));
    }
    r.ok = true;
    r.ms_total = r.ms_features + r.ms_descriptors + msSince(t_start);
    return r;
}

EgomotionResult EgomotionEstimator::estimate(
    const emslam::stereo::StereoFrame& prev, const emslam::stereo::StereoFrame& cur) const
{
    const Described dp = describe(prev);
    const Described dc = describe(cur);
    EgomotionResult r = estimateDescribed(dp, dc, nullptr, true);
    // Stateless use describes both frames: charge both to this step.
    r.ms_features += dp.ms_features;
    r.ms_descriptors += dp.ms_descriptors;
    r.ms_total += dp.ms_features + dp.ms_descriptors;
    return r;
}

EgomotionResult EgomotionEstimator::estimate(const Description& prev, const Description& cur) const
{
    if (!prev || !cur)
    {
        throw std::invalid_argument("EgomotionEstimator::estimate: no description of a frame");
    }
    return estimateDescribed(*prev, *cur, nullptr, false);
}

std::size_t EgomotionEstimator::CompactDescription::bytes() const
{
    return sizeof(*this) + features.size() * sizeof(Feature) + codes.size() +
           scales.size() * sizeof(float);
}

EgomotionEstimator::CompactDescription EgomotionEstimator::compact(
    const Description& d, std::size_t max_features)
{
    CompactDescription c;
    if (!d)
    {
        return c;
    }
    c.camera = d->camera;
    c.baseline = d->baseline;
    c.dim = d->descriptors.dim;
    const std::size_t n = std::min(d->features.size(), d->descriptors.size());
    // Rows of a flat window are zero: they match nothing, so they go first.
    std::vector<std::size_t> usable;
    for (std::size_t i = 0; i < n; ++i)
    {
        const float* row = d->descriptors.row(i);
        if (std::any_of(row, row + c.dim, [](float v) { return v != 0.0f; }))
        {
            usable.push_back(i);
        }
    }
    if (max_features > 0 && usable.size() > max_features)
    {
        // The strongest gradients of each cell of an 8 x 6 grid in turn, so
        // the kept features cover the image as the matches of a registration
        // need, rather than crowding on the most contrasted object.
        constexpr int GRID_X = 8, GRID_Y = 6;
        const double w = std::max<double>(1, d->camera.ncols),
                     h = std::max<double>(1, d->camera.nrows);
        std::sort(
            usable.begin(), usable.end(),
            [&](std::size_t a, std::size_t b)
            { return d->features[a].gradient_magnitude > d->features[b].gradient_magnitude; });
        std::vector<int> taken(GRID_X * GRID_Y, 0);
        std::vector<std::pair<int, std::size_t>> ranked;  // (rank in its cell, feature)
        ranked.reserve(usable.size());
        for (std::size_t i : usable)
        {
            const auto& f = d->features[i];
            const int cx = std::clamp(static_cast<int>(f.u * GRID_X / w), 0, GRID_X - 1);
            const int cy = std::clamp(static_cast<int>(f.v * GRID_Y / h), 0, GRID_Y - 1);
            ranked.emplace_back(taken[static_cast<std::size_t>(cy * GRID_X + cx)]++, i);
        }
        std::stable_sort(
            ranked.begin(), ranked.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
        usable.clear();
        for (std::size_t k = 0; k < max_features; ++k)
        {
            usable.push_back(ranked[k].second);
        }
        std::sort(usable.begin(), usable.end());
    }
    c.features.reserve(usable.size());
    c.codes.reserve(usable.size() * static_cast<std::size_t>(c.dim));
    c.scales.reserve(usable.size());
    for (std::size_t i : usable)
    {
        c.features.push_back(d->features[i]);
        const float* row = d->descriptors.row(i);
        float peak = 0;
        for (int k = 0; k < c.dim; ++k)
        {
            peak = std::max(peak, std::abs(row[k]));
        }
        c.scales.push_back(peak / 127.0f);
        for (int k = 0; k < c.dim; ++k)
        {
            c.codes.push_back(static_cast<std::int8_t>(std::lround(row[k] / peak * 127.0f)));
        }
    }
    return c;
}

EgomotionEstimator::Description EgomotionEstimator::expand(const CompactDescription& c)
{
    if (c.features.empty() || c.dim <= 0)
    {
        return nullptr;
    }
    auto d = std::make_shared<Described>();
    d->features = c.features;
    d->camera = c.camera;
    d->baseline = c.baseline;
    d->descriptors.dim = c.dim;
    d->descriptors.data.resize(c.codes.size());
    const auto dim = static_cast<std::size_t>(c.dim);
    for (std::size_t i = 0; i < c.features.size(); ++i)
    {
        float* row = d->descriptors.data.data() + i * dim;
        double mean = 0;
        for (std::size_t k = 0; k < dim; ++k)
        {
            row[k] = static_cast<float>(c.codes[i * dim + k]) * c.scales[i];
            mean += row[k];
        }
        mean /= static_cast<double>(dim);
        double norm2 = 0;
        for (std::size_t k = 0; k < dim; ++k)
        {
            row[k] -= static_cast<float>(mean);
            norm2 += static_cast<double>(row[k]) * row[k];
        }
        const auto inv = static_cast<float>(norm2 > 0 ? 1.0 / std::sqrt(norm2) : 0.0);
        for (std::size_t k = 0; k < dim; ++k)
        {
            row[k] *= inv;
        }
    }
    return d;
}

EgomotionResult EgomotionEstimator::process(const emslam::stereo::StereoFrame& cur)
{
    auto d = std::make_shared<Described>(describe(cur));
    EgomotionResult r;
    if (!m_prev)
    {
        r.features_cur = d->features.size();
        r.ms_features = d->ms_features;
        r.ms_descriptors = d->ms_descriptors;
        r.ms_total = r.ms_features + r.ms_descriptors;
        r.failure_reason = "first frame";
    }
    else
    {
        r = estimateDescribed(*m_prev, *d, m_velocity ? &*m_velocity : nullptr, true);
        if (r.ok)
        {
            m_velocity = r.T_prev_cur;  // a failed step keeps the last velocity
        }
    }
    m_prev = std::move(d);
    return r;
}

void EgomotionEstimator::reset()
{
    m_prev.reset();
    m_velocity.reset();
}

}  // namespace emslam::egomotion
