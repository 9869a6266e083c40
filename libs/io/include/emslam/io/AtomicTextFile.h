// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/OutputFile.h>

#include <memory>
#include <ostream>
#include <string>

namespace emslam::io
{
/** A text output written to `<file>.partial` and renamed to `file` by
 * commit(), so a reader never sees half a file and a failed run never
 * leaves one under the final name (the `.partial` file is removed if
 * commit() is never reached). A symbolic link is followed and its target
 * written; anything else that is not a regular file is refused (see
 * requireOutputFile()).
 * \ingroup emslam_io_grp \sa writeTextAtomically() */
class AtomicTextFile
{
public:
    /** Throws std::runtime_error naming `file` if it cannot be created, or
     * if it exists and is not a regular file (a folder, a device, ...). */
    explicit AtomicTextFile(std::string file);
    ~AtomicTextFile();
    AtomicTextFile(const AtomicTextFile&) = delete;
    AtomicTextFile& operator=(const AtomicTextFile&) = delete;

    /** Where the text goes (the temporary file until commit()). */
    std::ostream& stream() { return m_out->text(); }
    /** Writes the rest, closes and renames; throws std::runtime_error naming
     * the file and the OS reason on any error ("cannot write 'FILE': No
     * space left on device", see OutputFile). */
    void commit();

private:
    std::string m_file, m_tmp;
    std::unique_ptr<OutputFile> m_out;
    bool m_committed{false};
};

/** `text` written to `file` through an AtomicTextFile. \ingroup emslam_io_grp */
void writeTextAtomically(const std::string& file, const std::string& text);

}  // namespace emslam::io
