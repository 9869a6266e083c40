// SPDX-License-Identifier: BSD-3-Clause
#pragma once

namespace emslam::rectify
{
/** Registers this library's MRPT classes. Mains and test mains call it, which
 * also keeps the linker from dropping the library. Idempotent. */
void registerAllClasses();
}  // namespace emslam::rectify
