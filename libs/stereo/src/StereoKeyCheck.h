// SPDX-License-Identifier: BSD-3-Clause
// Private to emslam_stereo (not installed): the [StereoMatcher] value check shared by
// StereoMatcher and SparseStereoMatcher.
#pragma once

#include <sstream>
#include <stdexcept>

namespace emslam::stereo
{
/** Throws std::invalid_argument "[StereoMatcher] KEY = VALUE: must be RANGE" unless `ok`. */
template <typename T>
void requireStereo(bool ok, const char* key, const T& value, const char* range)
{
    if (!ok)
    {
        std::ostringstream msg;
        msg << "[StereoMatcher] " << key << " = " << value << ": must be " << range;
        throw std::invalid_argument(msg.str());
    }
}

}  // namespace emslam::stereo
