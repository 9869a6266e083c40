// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace emslam::io
{
/** Writes `image` to `file` in the format its extension names (`.png`,
 * ...): encoded in memory by cv::imencode(), written by OutputFile, so a
 * failure names the file and the OS reason ("cannot write 'map_top.png':
 * No space left on device"); cv::imwrite() only returns false, and not even
 * that when the file's close fails. `name`: the file named in messages
 * (empty: `file`). Not atomic: see writeFileAtomically().
 * \ingroup emslam_io_grp \sa OutputFile */
void writeImageFile(const std::string& file, const cv::Mat& image, const std::string& name = {});

}  // namespace emslam::io
