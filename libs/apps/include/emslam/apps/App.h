// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/CommandLine.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace emslam::apps
{
/** What every emslam program shares, as a non-virtual interface: initialize()
 * parses the command line through the program's parseArguments() (`--help`
 * and `--version` make helpRequested() true and run() a no-op), run() runs
 * its execute(). The options most programs take are built here, read once
 * the command line is parsed (parseCommandLine()) and checked the same way in
 * every program:
 * - `--set Section.key=value` (addSetOption()), applied over the INI file by
 *   loadParameters(), each key checked against the program's known keys with
 *   a "did you mean" suggestion;
 * - `--max-frames N` (addMaxFramesOption(), a count ≥ 0) and `--quiet`
 *   (addQuietOption()).
 * appMain() runs an App from main().
 * \ingroup emslam_apps_grp */
class App
{
public:
    virtual ~App() = default;
    App(const App&) = delete;
    App& operator=(const App&) = delete;

    /** Parses the command line; throws std::invalid_argument on bad
     * arguments (and whatever the program's own checks throw). */
    void initialize(int argc, const char** argv);
    /** As initialize() above, for main()'s non-const `argv`. */
    void initialize(int argc, char** argv) { initialize(argc, const_cast<const char**>(argv)); }
    /** Runs the program; does nothing after `--help` / `--version`. */
    void run();
    /** True after `--help` or `--version`: run() then does nothing. */
    bool helpRequested() const { return m_help_requested; }

    /** Effective configuration (the INI file plus `--set`), for programs that
     * read one; tests may edit it between initialize() and run(). */
    mrpt::config::CConfigFileMemory params;

protected:
    /** `program`: the name users type ("emslam-mapper"), for messages. */
    explicit App(const char* program) : m_program(program) {}

    /** The name users type, e.g. "emslam-mapper". */
    const char* program() const { return m_program; }

    /** The program's command line: builds its TCLAP::CmdLine (with the
     * shared options it takes), calls parseCommandLine() and reads the
     * values. Returns false after `--help` / `--version`. */
    virtual bool parseArguments(int argc, const char** argv) = 0;
    /** The program's work (after a successful parseArguments()). */
    virtual void execute() = 0;

    /** emslam::apps::parseCommandLine() under this program's name, then the
     * shared options are read and checked. */
    bool parseCommandLine(
        TCLAP::CmdLine& cmd,
        int argc,
        const char** argv,
        const std::vector<DeprecatedSpelling>& deprecated = {});

    /** Registers `--set SECTION.key=value` (repeatable) on `cmd`. */
    void addSetOption(TCLAP::CmdLine& cmd, const std::string& help);
    /** Registers `--max-frames N` on `cmd` (0: all). */
    void addMaxFramesOption(TCLAP::CmdLine& cmd, const std::string& help);
    /** Registers `-q`, `--quiet` on `cmd`. */
    void addQuietOption(TCLAP::CmdLine& cmd, const std::string& help);

    /** The `--set` items given (empty without addSetOption()). */
    const std::vector<std::string>& overrides() const;
    /** `--max-frames` (0: all, or no such option). */
    std::size_t maxFrames() const { return m_max_frames; }
    /** `--quiet` given. */
    bool quiet() const { return m_quiet; }

    /** params = `config_file` (when not empty) + the `--set` overrides; with
     * `known`, every `--set` key must be one of its keys (see
     * requireValidOverrides()). */
    void loadParameters(
        const std::string& config_file, const mrpt::config::CConfigFileBase* known = nullptr);

    /** "bad command line: MESSAGE; try PROGRAM --help", thrown. */
    [[noreturn]] void usageError(const std::string& message) const;

private:
    const char* m_program;
    bool m_help_requested{false};
    std::unique_ptr<TCLAP::MultiArg<std::string>> m_set_arg;
    std::unique_ptr<TCLAP::ValueArg<long long>> m_max_frames_arg;
    std::unique_ptr<TCLAP::SwitchArg> m_quiet_arg;
    std::size_t m_max_frames{0};
    bool m_quiet{false};
};

}  // namespace emslam::apps
