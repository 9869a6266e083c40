// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/slam/Relocalizer.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace emslam::slam
{
namespace
{
/** χ²(6) at 99.73 %: two placings of one frame agree within this. */
constexpr double AGREE_CHI2_6DOF = 20.06;
/** Registrations that must agree on the pose. */
constexpr std::size_t MIN_AGREEING = 2;
/** Standard deviations by which the winning place's inliers must exceed
 * those of the best place that disagrees (counts: Poisson). */
constexpr double SIGNIFICANCE_SIGMAS = 3.0;
}  // namespace

Relocalizer::Relocalizer(std::vector<Place> places, const TOptions& options)
    : m_places(std::move(places)), m_options(options)
{
    m_options.candidates = std::max(m_options.candidates, MIN_AGREEING);
    m_options.covariance_scale = std::max(1.0, m_options.covariance_scale);
    for (std::size_t i = 0; i < m_places.size(); ++i)
    {
        m_index.add(i, m_places[i].kept);
    }
}

std::optional<Relocalizer::Fix> Relocalizer::registerAt(
    std::size_t place,
    const emslam::egomotion::EgomotionEstimator::Description& frame,
    const emslam::egomotion::EgomotionEstimator& estimator) const
{
    const Place& p = m_places[place];
    const auto described = emslam::egomotion::EgomotionEstimator::expand(p.kept);
    if (!described)
    {
        return std::nullopt;
    }
    const auto r = estimator.estimate(described, frame);
    if (!r.ok)
    {
        return std::nullopt;
    }
    Fix f;
    f.place = place;
    f.T_world_frame = p.pose + r.T_prev_cur;
    emslam::rectify::ActionCovariance c = r.has_covariance ? r.covariance : p.covariance;
    c *= m_options.covariance_scale;
    c += p.covariance;
    f.covariance = c;
    f.matches = r.final_matches;
    return f;
}

std::vector<std::size_t> Relocalizer::placesNear(const mrpt::poses::CPose3D& pose) const
{
    std::vector<std::pair<double, std::size_t>> near;
    for (std::size_t i = 0; i < m_places.size(); ++i)
    {
        if (samePlace(m_places[i].pose, pose))
        {
            near.emplace_back((pose - m_places[i].pose).norm(), i);
        }
    }
    std::sort(near.begin(), near.end());
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < near.size() && out.size() < m_options.candidates; ++i)
    {
        out.push_back(near[i].second);
    }
    return out;
}

bool Relocalizer::agree(const Fix& a, const Fix& b)
{
    const auto delta = emslam::rectify::actionDifference(a.T_world_frame, b.T_world_frame);
    const double d2 =
        2 * emslam::rectify::halfMahalanobis(
                delta, emslam::rectify::informationOf(a.covariance + b.covariance, 6));
    return d2 <= AGREE_CHI2_6DOF;
}

bool Relocalizer::samePlace(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b) const
{
    const mrpt::poses::CPose3D d = b - a;
    return d.norm() <= m_options.max_distance &&
           emslam::rectify::rotationAngle(d) <= m_options.max_angle;
}

bool Relocalizer::significantlyFewer(std::size_t a, std::size_t b)
{
    const auto n = static_cast<double>(b), r = static_cast<double>(a);
    return n - r > SIGNIFICANCE_SIGMAS * std::sqrt(n + r);
}

std::optional<Relocalizer::Fix> Relocalizer::strongestAgreed(
    const std::vector<Fix>& fixes, const mrpt::poses::CPose3D* near) const
{
    std::optional<Fix> best;
    for (const Fix& a : fixes)
    {
        if (a.agreeing >= MIN_AGREEING && (!near || samePlace(*near, a.T_world_frame)) &&
            (!best || a.matches > best->matches))
        {
            best = a;
        }
    }
    return best;
}

bool Relocalizer::clearlyBest(const Fix& best, const std::vector<Fix>& fixes) const
{
    // A rival is another place: beyond where the loop closer looks for a
    // revisit of it (registrations a few centimetres apart that fail the
    // strict χ² are the same place, placed by a map of its own errors).
    for (const Fix& b : fixes)
    {
        if (!samePlace(best.T_world_frame, b.T_world_frame) &&
            !significantlyFewer(b.matches, best.matches))
        {
            return false;
        }
    }
    return true;
}

std::optional<Relocalizer::Fix> Relocalizer::locate(
    const emslam::egomotion::EgomotionEstimator::Description& frame,
    const emslam::egomotion::EgomotionEstimator& estimator,
    const std::optional<mrpt::poses::CPose3D>& prior) const
{
    using emslam::egomotion::EgomotionEstimator;
    if (!frame || m_places.empty())
    {
        return std::nullopt;
    }
    // 1. The places that look most like the frame.
    const auto kept = EgomotionEstimator::compact(frame, m_places.front().kept.features.size());
    std::vector<Fix> fixes;
    std::vector<bool> tried(m_places.size(), false);
    std::size_t registrations = 0;
    for (const auto& m : m_index.query(kept, m_places.size(), m_options.candidates))
    {
        tried[m.place] = true;
        ++registrations;
        if (auto f = registerAt(m.place, frame, estimator))
        {
            fixes.push_back(*f);
        }
    }
    if (fixes.empty())
    {
        return std::nullopt;
    }
    // 2. Where the strongest registration puts the frame, the places near
    // it (facing its way) must register it there too. A periodic corridor
    // fools consecutive keyframes alike, so a group of them is no more
    // evidence than its best member: groups compare by their best.
    const auto strongest = std::max_element(
        fixes.begin(), fixes.end(),
        [](const Fix& a, const Fix& b) { return a.matches < b.matches; });
    std::vector<std::size_t> near = placesNear(strongest->T_world_frame);
    if (prior)
    {
        // And the places at the prior, which may be a look-alike's equal.
        const std::vector<std::size_t> at_prior = placesNear(*prior);
        near.insert(near.end(), at_prior.begin(), at_prior.end());
    }
    for (const std::size_t i : near)
    {
        if (!tried[i])
        {
            tried[i] = true;
            ++registrations;
            if (auto f = registerAt(i, frame, estimator))
            {
                fixes.push_back(*f);
            }
        }
    }
    // 3. The best place must be agreed with, and beat every other place by
    // more than the counts' noise; with a prior, among places it cannot
    // tell apart, the one at the prior.
    for (Fix& a : fixes)
    {
        a.agreeing = 0;
        for (const Fix& b : fixes)
        {
            a.agreeing += agree(a, b) ? 1 : 0;
        }
    }
    std::optional<Fix> best = strongestAgreed(fixes, nullptr);
    if (!best)
    {
        return std::nullopt;
    }
    if (!clearlyBest(*best, fixes))
    {
        const std::optional<Fix> at_prior = prior ? strongestAgreed(fixes, &*prior) : std::nullopt;
        if (!at_prior || significantlyFewer(at_prior->matches, best->matches))
        {
            return std::nullopt;  // a look-alike as good: wait for a frame that tells them apart
        }
        best = at_prior;
    }
    best->tried = registrations;
    return best;
}

}  // namespace emslam::slam
