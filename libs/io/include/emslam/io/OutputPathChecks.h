// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <string>
#include <vector>

namespace emslam::io
{
/** The file an output named `file` is really written to, checked before any
 * work (every emslam writer goes through it):
 * - a symbolic link is followed, through every link, and its target is
 *   written: the link itself stays, as with a shell redirection;
 * - what is there must be a regular file or nothing: a folder, a device
 *   (`/dev/null`), a FIFO or a socket is refused, since the writers rename a
 *   finished `.partial` file over their output;
 * - its folder must exist and take a new file (a probe file is created and
 *   removed at once).
 *
 * Throws std::runtime_error naming `what` (e.g. "output rawlog") and `file`.
 * \ingroup emslam_io_grp \sa requireOutputFolder(), requireInputFile() */
std::string requireOutputFile(const std::string& file, const std::string& what);

/** Checks, before any work, that `folder` can take outputs: it is a folder
 * (or a symbolic link to one) in which a probe file can be created, or it
 * does not exist yet and its nearest existing ancestor is such a folder
 * (createOutputFolder() makes it when the outputs are written). Throws
 * std::runtime_error naming `what` and `folder`.
 * \ingroup emslam_io_grp */
void requireOutputFolder(const std::string& folder, const std::string& what);

/** Refuses (std::runtime_error) any of `names` inside `folder` that exists
 * and is not a regular file: a folder, a device, a FIFO, a socket, or a
 * symbolic link (the outputs of a folder replace their files, so a link
 * would be replaced, never followed). \ingroup emslam_io_grp */
void requireReplaceableFiles(const std::string& folder, const std::vector<std::string>& names);

/** Creates `folder` and its missing parents (like `mkdir -p`); throws
 * std::runtime_error naming it if it cannot. \ingroup emslam_io_grp */
void createOutputFolder(const std::string& folder);

}  // namespace emslam::io
