// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/GzOutputStream.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <memory>
#include <string>

namespace emslam::io
{
/** A gz-compressed rawlog, and optionally its ground truth as a TUM file,
 * written to `FILE.partial` / `GT.partial` and renamed to `FILE` / `GT` by
 * commit(), so that a failed run never leaves a truncated output behind: the
 * destructor removes the `.partial` files unless commit() succeeded. An
 * output that is a symbolic link is written through: its target gets the
 * data and the link stays.
 * \code
 * RawlogOutput::checkOutputFolders(file, gt_file);  // before any work
 * RawlogOutput out(file, gz_level, gt_file);
 * out.archive() << *obs;  // ...
 * poses_written = out.commit(gt);
 * \endcode
 * \ingroup emslam_io_grp \sa RawlogInput, ProgressLine */
class RawlogOutput
{
public:
    /** Checks `file`, and `gt_file` when it is not empty, with
     * requireOutputFile() before any work: throws std::runtime_error if one
     * exists and is not a regular file (or a symbolic link to one), or if its
     * folder does not exist or is not writable. */
    static void checkOutputFolders(const std::string& file, const std::string& gt_file);

    /** Creates `file + ".partial"` with gzip level `gz_level` (0..9); throws
     * std::runtime_error if it cannot be created. `gt_file`: where commit()
     * writes the ground truth (empty: nowhere). A failed write (a full disk)
     * throws from the archive, and a failed close from commit(), naming
     * `file` and the OS reason (see GzOutputStream). */
    RawlogOutput(const std::string& file, int gz_level, const std::string& gt_file = {});
    /** Removes the `.partial` files unless commit() succeeded. */
    ~RawlogOutput();

    RawlogOutput(const RawlogOutput&) = delete;
    RawlogOutput& operator=(const RawlogOutput&) = delete;

    /** Where the data goes until commit(): the output's `.partial` file. */
    const std::string& partialFile() const { return m_partial; }

    /** The archive to serialize observations into. */
    mrpt::serialization::CArchive& archive() { return *m_archive; }

    /** Closes the rawlog, saves `ground_truth` to `GT.partial` (if a ground-truth
     * file was given), then renames the rawlog and the ground truth to their
     * final names. Returns the number of poses written to the ground-truth
     * file (0 without one). Throws on failure (the destructor then cleans up). */
    std::size_t commit(const emslam::io::TumTrajectory& ground_truth = {});

    /** After a write error (a full disk), instead of commit(): closes the
     * rawlog ignoring errors and renames it to its final name, readable up to
     * its last complete record (a recording keeps what it got). No ground
     * truth is written. */
    void keepWhatWasWritten();

private:
    std::string m_file;
    std::string m_partial;
    std::string m_gt_file;
    std::string m_gt_partial;
    std::unique_ptr<GzOutputStream> m_stream;
    std::unique_ptr<mrpt::serialization::CArchive> m_archive;
    bool m_committed{false};
};

}  // namespace emslam::io
