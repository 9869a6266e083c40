// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <string>

namespace emslam::io
{
/** The shortest decimal text that reads back to the same double; `null` for
 * NaN and infinities (JSON has no such numbers). \ingroup emslam_io_grp */
std::string jsonNumber(double v);

/** `s` as a quoted JSON string, with quotes, backslashes and control
 * characters escaped. \ingroup emslam_io_grp */
std::string jsonString(const std::string& s);

}  // namespace emslam::io
