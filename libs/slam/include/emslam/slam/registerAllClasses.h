// SPDX-License-Identifier: BSD-3-Clause
#pragma once

namespace emslam::slam
{
/** Registers the MRPT classes EntropySlam uses: those of libs/stereo,
 * libs/egomotion, libs/maps and libs/rectify, and MRPT's own maps (for
 * CMultiMetricMap). A program that maps with EntropySlam calls it once (it
 * also keeps the linker from dropping the libraries). Idempotent. */
void registerAllClasses();
}  // namespace emslam::slam
