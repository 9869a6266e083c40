// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <string>

namespace emslam::io
{
/** The text of the INI file `file` (a `what`, e.g. "config file", for
 * messages), read the one way every config reader of emslam reads one:
 * checked first with requireInputFile(file, what, MAX_INI_BYTES) (a device,
 * a folder or a file above 16 MiB fails before any byte is read), read with
 * the same cap (a file growing meanwhile stops there), then checked with
 * requireUniqueIniEntries(). Throws std::runtime_error naming the file and
 * the OS reason if it cannot be read, std::invalid_argument from
 * requireUniqueIniEntries(). Give the text to
 * `mrpt::config::CConfigFileMemory`.
 * \ingroup emslam_io_grp \sa requireUniqueIniEntries() */
std::string readIniFile(const std::string& file, const std::string& what);

/** Throws std::invalid_argument if the INI text `text` (from `file`, named
 * in the message) repeats a section or sets a key of a section twice: MRPT
 * 2.5.8 merges repeated sections and keeps the last value of a key without a
 * word, so a copy-pasted block silently overrides the one a user edits.
 * The message has one line per repetition, naming both lines:
 * \code
 * world.ini:12: key 'fps' repeated in [Simulation] (first at world.ini:7)
 * world.ini:20: section [Camera] repeated (first at world.ini:3)
 * world.ini:21: key 'FPS' repeated in [Simulation] (first at world.ini:7 as 'fps'; names ignore
 * case) \endcode
 *
 * "The same" is what MRPT reads as the same. CConfigFile and
 * CConfigFileMemory first run `mrpt::config::config_parser()` (`@define`,
 * `${VAR}`, `$eval{}`, `$env{}`, and a `\` at a line's end joining the next
 * line), then SimpleIni's `CSimpleIniA` parses the result: a line whose
 * first non-blank character is `;` or `#` is a comment; `[name]` opens a
 * section (blanks around the name dropped, the rest of the line ignored);
 * `key = value` sets a key (blanks around the key dropped); a line without
 * `=`, or with nothing before it, is ignored; keys before any section belong
 * to the section named "" (as does `[]`). Section and key names compare
 * ignoring ASCII case (`SI_NoCase`). Line numbers are those of the file
 * before preprocessing.
 *
 * Two things MRPT reads wrongly without a word are refused here as well: a
 * line starting with `[` without a closing `]` (SimpleIni then files the
 * following keys under a garbled section name) and a NUL byte (SimpleIni
 * stops reading there). A preprocessor error (an unknown `${VAR}`, ...) is
 * thrown with the file's name.
 * \ingroup emslam_io_grp \sa readIniFile() */
void requireUniqueIniEntries(const std::string& text, const std::string& file);

}  // namespace emslam::io
