// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::apps
{
/** An old spelling of an argument that is still accepted for one release,
 * with a warning on stderr: `--rawlog FILE` where the rawlog is now the first
 * positional argument, or `--poses FILE` now spelled `--gt FILE`.
 * \ingroup emslam_apps_grp \sa parseCommandLine() */
struct DeprecatedSpelling
{
    /** The old flag, e.g. "--rawlog" (always followed by one value). */
    std::string old_flag;
    /** The flag that replaces it, e.g. "--gt"; empty: its value became the
     * positional argument number `position` (0: the first). */
    std::string new_flag;
    /** With an empty `new_flag`: which positional argument the value became. */
    std::size_t position{0};
    /** How --help names the replacement, e.g. "DATASET.rawlog". */
    std::string new_name;
};

/** Parses `argv` with `cmd` without letting TCLAP call exit(): returns false
 * when `--help` or `--version` was handled (the text is already printed), true
 * when the App should run, and throws std::invalid_argument on bad arguments
 * with TCLAP's message, the missing required arguments named (TCLAP only says
 * "One or more required arguments missing!") and a pointer to --help.
 *
 * argv[0] is replaced by `program`, so usage and error texts name the program
 * as users type it, whatever path started it. The `deprecated` spellings are
 * rewritten first (see rewriteDeprecatedSpellings()).
 * \ingroup emslam_apps_grp */
bool parseCommandLine(
    TCLAP::CmdLine& cmd,
    const char* program,
    int argc,
    const char** argv,
    const std::vector<DeprecatedSpelling>& deprecated = {});

/** `args` (without the program name) with every `OLD VALUE` / `OLD=VALUE` of
 * `deprecated` rewritten to its new spelling, and a warning for each printed
 * to stderr as "<program>: warning: ...". Values of old flags that became
 * positional go first, in position order; throws std::invalid_argument when
 * they cannot stand there (a position given twice, or a gap: old and new
 * spellings mixed) or when an old flag lacks its value.
 * \ingroup emslam_apps_grp */
std::vector<std::string> rewriteDeprecatedSpellings(
    const std::string& program,
    const std::vector<std::string>& args,
    const std::vector<DeprecatedSpelling>& deprecated);

/** `args` (without the program name) checked against the options of `cmd`
 * before TCLAP sees them: a word that looks like an option ("-x", "--name",
 * "--name=value"; not a negative number, nor the value of the option before
 * it, nor anything after "--") and is none of `cmd`'s throws
 * std::invalid_argument "unknown option '--bogus'; try PROGRAM --help" (TCLAP
 * would report a required argument it never reached instead). Returns `args`
 * with `--name=value` split into `--name value`. \ingroup emslam_apps_grp */
std::vector<std::string> requireKnownOptions(
    TCLAP::CmdLine& cmd, const std::string& program, const std::vector<std::string>& args);

/** "bad command line: MESSAGE; try PROGRAM --help", thrown as
 * std::invalid_argument. \ingroup emslam_apps_grp \sa App::usageError() */
[[noreturn]] void usageError(const std::string& program, const std::string& message);

/** `description` followed by " (default: `value`)", for --help texts.
 * \ingroup emslam_apps_grp */
std::string withDefault(const std::string& description, const std::string& value);

/** `value`, given to the count option `flag` (e.g. "--max-frames"), once
 * checked to be at least `min`: throws std::invalid_argument ("--segment-step
 * must be at least 1 (got -1); try PROGRAM --help") otherwise. Count options
 * are read as signed numbers and checked here: TCLAP reads "-1" into an
 * unsigned one as a huge count, silently.
 * \ingroup emslam_apps_grp */
std::size_t countOption(
    long long value, const std::string& flag, long long min, const std::string& program);

/** Checks each `--set Section.key=value` item against `reference` (every
 * valid section and key, e.g. the parameter structs saved into it): the
 * section and key must exist (with a "did you mean" suggestion otherwise) and
 * a numeric or boolean key needs a value of that kind. Throws
 * std::invalid_argument naming every bad item. \ingroup emslam_apps_grp
 * \sa requireValidConfig() */
void requireValidOverrides(
    const std::vector<std::string>& sets, const mrpt::config::CConfigFileBase& reference);

/** Applies `--set Section.key=value` overrides to `cfg`. Throws
 * std::invalid_argument on a malformed item.
 * \ingroup emslam_apps_grp */
void applyConfigOverrides(
    mrpt::config::CConfigFileMemory& cfg, const std::vector<std::string>& sets);

/** Fills `cfg` from the INI file `config_file` (when not empty), then applies
 * the `--set` overrides `sets` (see applyConfigOverrides()). Sections and
 * keys under their old names (slam::configRenames()) are read under the new
 * ones, with a warning on std::cerr for each. The file is read
 * by io::readIniFile(): it throws if the file is not a regular file of at
 * most io::MAX_INI_BYTES, or if it repeats a section or a key.
 * \ingroup emslam_apps_grp */
void loadConfig(
    mrpt::config::CConfigFileMemory& cfg,
    const std::string& config_file,
    const std::vector<std::string>& sets);

}  // namespace emslam::apps
