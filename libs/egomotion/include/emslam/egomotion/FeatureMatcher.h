// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/Feature.h>
#include <emslam/egomotion/LogPolarDescriptor.h>

#include <opencv2/core/types.hpp>
#include <vector>

namespace emslam::egomotion
{
/** Stage 2b of §2.1: appearance matching. S = |rho| of the normalised
 * descriptors (one matrix product), kept when S >= similarity_min and the two
 * features are each other's best (mutual consistency).
 *
 * Exhaustive: O(|prev| |cur| dim), computed in blocks of rows so memory stays
 * O(|cur|). A pair needs S > 0, so zero rows match nothing; among equal
 * scores the lowest index is the best. Matches come sorted by `prev`.
 * \ingroup emslam_egomotion_grp \sa LogPolarDescriptorExtractor */
MatchList matchMutual(const Descriptors& prev, const Descriptors& cur, float similarity_min);

/** Guided matching: matchMutual() restricted to the pairs whose current
 * feature lies within `radius_px` of where the previous feature is predicted
 * to appear (`predicted[i]` for `prev` row i; a non-finite prediction matches
 * nothing). Best and mutual are taken over those pairs only, so a feature's
 * look-alike far away no longer competes. Current features are bucketed on a
 * grid of `radius_px` cells: O((|prev| k + |cur|) dim) for k candidates per
 * feature instead of O(|prev| |cur| dim). Matches come sorted by `prev`.
 * \ingroup emslam_egomotion_grp */
MatchList matchMutualGuided(
    const Descriptors& prev,
    const Descriptors& cur,
    const std::vector<cv::Point2f>& predicted,
    const FeatureList& cur_features,
    float radius_px,
    float similarity_min);

}  // namespace emslam::egomotion
