// SPDX-License-Identifier: BSD-3-Clause
#pragma once

namespace emslam::stereo
{
/** Registers the MRPT classes this library uses (and any of its own) with
 * MRPT's RTTI, so that rawlogs can be read. Mains and test mains call it: it
 * also keeps the linker from dropping the library. Idempotent. */
void registerAllClasses();
}  // namespace emslam::stereo
