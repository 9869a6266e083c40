// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <string>
#include <vector>

namespace emslam::apps
{
/** Parses `argv` with `cmd` without letting TCLAP call exit(): returns false
 * when `--help` or `--version` was handled (the text is already printed), true
 * when the App should run, and throws std::invalid_argument with TCLAP's
 * message (plus a pointer to --help) on bad arguments.
 * \ingroup emslam_apps_grp */
bool parseCommandLine(TCLAP::CmdLine& cmd, int argc, const char** argv);

/** Same, with argv[0] replaced by (or, if argc is 0, set to) `program`, so
 * usage and error texts name the program as users type it, whatever path
 * started it. \ingroup emslam_apps_grp */
bool parseCommandLine(TCLAP::CmdLine& cmd, const char* program, int argc, const char** argv);

/** Applies `--set Section.key=value` overrides to `cfg`. Throws
 * std::invalid_argument on a malformed item.
 * \ingroup emslam_apps_grp */
void applyConfigOverrides(
    mrpt::config::CConfigFileMemory& cfg, const std::vector<std::string>& sets);

/** Fills `cfg` from the INI file `config_file` (when not empty), then applies
 * the `--set` overrides `sets` (see applyConfigOverrides()). Throws
 * std::runtime_error if the file does not exist.
 * \ingroup emslam_apps_grp */
void loadConfig(
    mrpt::config::CConfigFileMemory& cfg,
    const std::string& config_file,
    const std::vector<std::string>& sets);

}  // namespace emslam::apps
