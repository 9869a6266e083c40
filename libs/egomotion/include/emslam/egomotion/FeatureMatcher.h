// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/Feature.h>
#include <emslam/egomotion/LogPolarDescriptor.h>

#include <opencv2/core/types.hpp>
#include <vector>

namespace emslam::egomotion
{
/** Distinctiveness of a match (not in the paper, which keeps any mutual best
 * above S_min): on a periodic texture a feature's true match and its
 * look-alikes one period away score nearly alike, and which of them wins is
 * up to the noise. A match is kept only if the best score is clearly above
 * the best of the candidates elsewhere in the image, on both sides of the
 * match: the Pearson distance 1 - S (half the squared distance of the
 * normalised descriptors) of the runner-up must be at least `ratio` times
 * the best's. The best's own distance measures the noise between two views
 * of one place, so the test scales with the images' noise rather than with a
 * fixed margin. Runners-up within `same_place_px` of the best (its own
 * descriptor window, shifted a little) do not count. `ratio` <= 1: off.
 * \ingroup emslam_egomotion_grp */
struct Distinctiveness
{
    float ratio{1};          //!< runner-up's distance over the best's needed (<= 1: off)
    float same_place_px{0};  //!< runners-up this close to the best [px] are the same place
    const FeatureList* prev_features{nullptr};  //!< pixels of the rows of `prev`
    const FeatureList* cur_features{nullptr};   //!< pixels of the rows of `cur`

    /** The test is on: ratio > 1 and both feature lists given. */
    bool enabled() const { return ratio > 1 && prev_features && cur_features; }
    /** Whether `best` stands clear of `runner_up` (both scores S). */
    bool clear(float best, float runner_up) const
    {
        return 1.0f - runner_up >= ratio * (1.0f - best);
    }
};

/** Stage 2b of §2.1: appearance matching. S = |rho| of the normalised
 * descriptors (one matrix product), kept when S >= similarity_min and the two
 * features are each other's best (mutual consistency).
 *
 * Exhaustive: O(|prev| |cur| dim), computed in blocks of rows so memory stays
 * O(|cur|). A pair needs S > 0, so zero rows match nothing; among equal
 * scores the lowest index is the best. Matches come sorted by `prev`. With
 * `distinct` enabled, S is computed twice (best, then runners-up) and a
 * match must also pass Distinctiveness::clear() on both sides.
 * \ingroup emslam_egomotion_grp \sa LogPolarDescriptorExtractor */
MatchList matchMutual(
    const Descriptors& prev,
    const Descriptors& cur,
    float similarity_min,
    const Distinctiveness& distinct = {});

/** Guided matching: matchMutual() restricted to the pairs whose current
 * feature lies within `radius_px` of where the previous feature is predicted
 * to appear (`predicted[i]` for `prev` row i; a non-finite prediction matches
 * nothing). Best and mutual are taken over those pairs only, so a feature's
 * look-alike far away no longer competes. Current features are bucketed on a
 * grid of `radius_px` cells: O((|prev| k + |cur|) dim) for k candidates per
 * feature instead of O(|prev| |cur| dim). Matches come sorted by `prev`;
 * with `distinct`, runners-up are sought among the same candidates.
 * \ingroup emslam_egomotion_grp */
MatchList matchMutualGuided(
    const Descriptors& prev,
    const Descriptors& cur,
    const std::vector<cv::Point2f>& predicted,
    const FeatureList& cur_features,
    float radius_px,
    float similarity_min,
    const Distinctiveness& distinct = {});

}  // namespace emslam::egomotion
