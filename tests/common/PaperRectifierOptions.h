// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/RectifierOptions.h>

namespace emslam::test
{
/** The paper's search (§2.2.3): the entropy alone (no odometry prior) and box
 * proposals U(−ε, +ε); every other option at its default. What the tests
 * of the rectifier's algorithm start from (the defaults are the shipped
 * tuning, which adds the prior and the egomotion's covariance proposals). */
inline emslam::rectify::TRectifierOptions paperRectifierOptions()
{
    emslam::rectify::TRectifierOptions o;
    o.prior_weight = 0;
    o.prior_covariance = emslam::rectify::PriorCovariance::Fixed;
    o.proposal = emslam::rectify::ProposalShape::Box;
    return o;
}
}  // namespace emslam::test
