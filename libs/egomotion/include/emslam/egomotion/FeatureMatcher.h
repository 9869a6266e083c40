// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/Feature.h>
#include <emslam/egomotion/LogPolarDescriptor.h>

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

}  // namespace emslam::egomotion
