// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::apps
{
/** One unknown section or key of a user's configuration.
 * \ingroup emslam_apps_grp */
struct ConfigProblem
{
    /** The section as the user spelled it. */
    std::string section;
    /** The key as the user spelled it; empty: the section itself is unknown. */
    std::string key;
    /** The closest valid name (a section, or a key of `section`); empty if
     * none is close. */
    std::string suggestion;
    /** For a known key with a malformed value: the value as the user wrote it
     * and what the key needs ("a number", "true or false ...");
     * `expected` is empty for unknown names. */
    ///@{
    std::string value, expected;
    ///@}

    /** E.g. "unknown key 'esp_xyz' in [Rectifier] (did you mean 'eps_xyz'?)",
     * "unknown section [Rectifer] (did you mean [Rectifier]?)" or
     * "[StereoMatcher] num_disparities = 'abc' is not a number". */
    std::string message() const;
};

/** Every section and key of `user` that `reference` lacks. `reference` holds
 * all valid sections and keys, e.g. every parameter struct written with
 * `saveToConfigFile()`.
 *
 * Names compare case-insensitively, as MRPT reads them: in MRPT 2.5.8,
 * CConfigFile and CConfigFileMemory store the text in a `CSimpleIniA`, which
 * SimpleIni defines with the `SI_NoCase` comparator (sections and keys), and
 * CConfigFileBase::sectionExists() / keyExists() compare with `_strcmpi`.
 * So `EPS_XYZ` in `[rectifier]` is read as `eps_xyz` of `[Rectifier]` and is
 * not a problem.
 *
 * Key names are compared without surrounding blanks, so `reference` may be
 * the very CConfigFileMemory the structs were saved into (MRPT stores those
 * keys padded to MRPT_SAVE_NAME_PADDING()) or that text parsed again.
 *
 * For an unknown section only the section is reported (not its keys). A
 * suggestion is the reference name at the smallest editDistance() when that
 * distance is at most max(2, length of the user's name / 3). Sections named in
 * `ignored_sections` (any case) are skipped. Problems come in the order of
 * `user.getAllSections()` / `getAllKeys()`. */
std::vector<ConfigProblem> findUnknownConfigEntries(
    const mrpt::config::CConfigFileBase& user,
    const mrpt::config::CConfigFileBase& reference,
    const std::vector<std::string>& ignored_sections = {});

/** Throws std::invalid_argument whose message lists every problem of
 * findUnknownConfigEntries(), one per line, if there is any. */
void requireKnownConfigEntries(
    const mrpt::config::CConfigFileBase& user,
    const mrpt::config::CConfigFileBase& reference,
    const std::vector<std::string>& ignored_sections = {});

/** Every value of `user` that MRPT would misread silently: where `reference`
 * holds a number or a boolean under the same section and key,
 * the user's text (as read_string() returns it: trimmed, without a trailing
 * `//` comment, `$eval{}` done) must be one too. MRPT 2.5.8's read_int() and
 * read_double() parse with atoi() / atof(), so "abc" reads as 0, "64x" as 64,
 * "64.9" as 64 and "2147483648" as -2147483648; read_bool() knows true/false
 * and yes/no and reads anything else with atoi() ("on" is false). So:
 * - a key whose reference is a whole number (an int key: MRPT saves doubles
 *   with a decimal point) takes a whole number in int's range;
 * - any other numeric key takes a number (`nan` and `inf` too: the
 *   parameter's validate() decides);
 * - a boolean key takes true/false, yes/no (any case) or 1/0.
 * Unknown sections and keys are left to findUnknownConfigEntries(). */
std::vector<ConfigProblem> findMalformedConfigValues(
    const mrpt::config::CConfigFileBase& user,
    const mrpt::config::CConfigFileBase& reference,
    const std::vector<std::string>& ignored_sections = {});

/** Throws std::invalid_argument with every problem of
 * findMalformedConfigValues(), joined by "; " (apps that read free-form
 * sections, where unknown keys are not errors). */
void requireWellFormedConfigValues(
    const mrpt::config::CConfigFileBase& user, const mrpt::config::CConfigFileBase& reference);

/** Throws std::invalid_argument listing every problem of
 * findUnknownConfigEntries() and findMalformedConfigValues(), one per line.
 * With `skip_unknown_sections`, sections that `reference` lacks are not
 * problems (an app that reads a few sections of a shared INI file), but
 * unknown keys of the sections it knows still are. */
void requireValidConfig(
    const mrpt::config::CConfigFileBase& user,
    const mrpt::config::CConfigFileBase& reference,
    const std::vector<std::string>& ignored_sections = {},
    bool skip_unknown_sections = false);

/** Levenshtein edit distance between `a` and `b` (insertions, deletions and
 * substitutions of one character each cost 1), ignoring ASCII case. */
std::size_t editDistance(const std::string& a, const std::string& b);

}  // namespace emslam::apps
