// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <functional>
#include <string>

namespace emslam::io
{
/** Where an atomic write of `file` goes first: `<file>.partial`, or with
 * `keep_extension` `<file>.partial<ext>` (for writers that choose the
 * format by the extension, as cv::imwrite does).
 * \ingroup emslam_io_grp \sa writeFileAtomically() */
std::string partialFileFor(const std::string& file, bool keep_extension = false);

/** Renames a finished `partial` file to `file`; throws std::runtime_error
 * naming both (and the cause) if it cannot. \ingroup emslam_io_grp */
void commitPartialFile(const std::string& partial, const std::string& file);

/** Writes `file` so that a reader never sees half of it and a failed write
 * never leaves one under its name: `write(partial)` writes
 * partialFileFor(file, keep_extension) and returns false (or throws) on
 * failure; the file is then renamed to `file`. On any failure the partial
 * file is removed and std::runtime_error names `file` and the reason, errno
 * as `write` left it ("cannot write 'FILE': No space left on device"; an
 * exception from `write` is passed on). Writers that can, write through
 * OutputFile or GzOutputStream, whose exceptions carry the reason captured
 * at the failing call.
 * \ingroup emslam_io_grp \sa AtomicTextFile */
void writeFileAtomically(
    const std::string& file,
    const std::function<bool(const std::string& partial)>& write,
    bool keep_extension = false);

}  // namespace emslam::io
