// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <string>
#include <vector>

namespace emslam::io
{
/** A path an app reads or writes, with what it is for messages
 * ("world file", "output rawlog"). \ingroup emslam_io_grp */
struct RolePath
{
    std::string what;  //!< what the path is for, e.g. "world file"
    std::string path;  //!< the path as given
};

/** Refuses, before any work, an output that would overwrite one of the
 * inputs (std::invalid_argument naming both, e.g. "output rawlog 'W.ini' is
 * the world file 'W.ini'; give another output"):
 * the same file (`stat` device and inode, so hard and symbolic links are
 * caught) or, when one does not exist yet, the same resolved path. A dataset
 * folder lists every file it reads as an input (`-o DIR/image_0/000000.png`
 * is then refused). Empty paths (outputs not asked for) are skipped.
 * \ingroup emslam_io_grp \sa requireOutputFile() */
void requireOutputsAreNotInputs(
    const std::vector<RolePath>& outputs, const std::vector<RolePath>& inputs);

/** `folder`/`name` for each of `names`, as the RolePath `what` of an output
 * folder's files (e.g. the mapper's `-o DIR` writes `DIR/summary.json`).
 * \ingroup emslam_io_grp */
std::vector<RolePath> filesOfOutputFolder(
    const std::string& folder, const std::vector<std::string>& names, const std::string& what);

}  // namespace emslam::io
