// SPDX-License-Identifier: BSD-3-Clause
#pragma once

namespace emslam::apps
{
/** Registers every emslam library's classes (and the MRPT classes they read).
 * Every main and test main calls it; it also keeps the linker from dropping
 * the libraries. Idempotent. */
void registerAllClasses();
}  // namespace emslam::apps
