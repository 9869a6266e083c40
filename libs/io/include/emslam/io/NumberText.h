// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <string>

namespace emslam::io
{
/** The shortest fixed-point text that reads back to the same double, without
 * an exponent (some tools split numbers at `e`): 2317340800.123456 stays
 * "2317340800.123456" where `%g` or a stream's default 6 digits would print
 * 2.31734e+09. Trajectory files and messages that quote numbers use it.
 * \ingroup emslam_io_grp */
std::string shortestFixed(double v);

/** The shortest text that reads back to the same double, fixed or with an
 * exponent, whichever is shorter: "2317340800.5", "1e+300". For messages
 * quoting numbers that may be absurd. \ingroup emslam_io_grp */
std::string shortestText(double v);

}  // namespace emslam::io
