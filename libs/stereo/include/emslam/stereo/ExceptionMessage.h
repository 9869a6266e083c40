// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <exception>
#include <string>

namespace emslam::stereo
{
/** The human part of an exception's text. MRPT exceptions embed source
 * locations and a call-stack backtrace in what(); this keeps only their
 * "Message:" lines (outermost first, joined by ": "), which is what a user
 * needs to see; a std::exception that MRPT_END wrapped gives its own text
 * without MRPT's header and backtrace. Other exceptions return what()
 * trimmed.
 * \ingroup emslam_stereo_grp */
std::string shortExceptionMessage(const std::exception& e);

}  // namespace emslam::stereo
