// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>

#include <mrpt/system/filesystem.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <vector>

namespace emslam::apps
{
namespace
{
/** MRPT's TCLAP prints parse errors and returns false, just as for --help;
 * this output turns the error into an exception so callers can tell them apart. */
class ThrowingOutput : public TCLAP::StdOutput
{
public:
    void failure(TCLAP::CmdLineInterface& c, TCLAP::ArgException& e) override
    {
        // TCLAP's argId() is blank when no single argument is to blame.
        const bool has_id = e.argId().find_first_not_of(' ') != std::string::npos;
        throw std::invalid_argument(
            "bad command line: " + e.error() + (has_id ? " (" + e.argId() + ")" : "") + "; try " +
            c.getProgramName() + " --help");
    }
};
}  // namespace

bool parseCommandLine(TCLAP::CmdLine& cmd, int argc, const char** argv)
{
    ThrowingOutput out;
    // setOutput() does not free the default output object; take it over.
    const std::unique_ptr<TCLAP::CmdLineOutput> default_output(cmd.getOutput());
    cmd.setOutput(&out);
    const bool run = cmd.parse(argc, argv);
    cmd.setOutput(nullptr);
    return run;
}

bool parseCommandLine(TCLAP::CmdLine& cmd, const char* program, int argc, const char** argv)
{
    std::vector<const char*> args(argv, argv + std::max(argc, 0));
    if (args.empty())
    {
        args.push_back(program);
    }
    args[0] = program;
    return parseCommandLine(cmd, static_cast<int>(args.size()), args.data());
}

void applyConfigOverrides(
    mrpt::config::CConfigFileMemory& cfg, const std::vector<std::string>& sets)
{
    for (const auto& s : sets)
    {
        const auto dot = s.find('.');
        const auto eq = s.find('=');
        if (dot == std::string::npos || eq == std::string::npos || dot == 0 || eq < dot + 2)
        {
            throw std::invalid_argument("--set expects SECTION.key=value, got '" + s + "'");
        }
        cfg.write(s.substr(0, dot), s.substr(dot + 1, eq - dot - 1), s.substr(eq + 1));
    }
}

void loadConfig(
    mrpt::config::CConfigFileMemory& cfg,
    const std::string& config_file,
    const std::vector<std::string>& sets)
{
    if (!config_file.empty())
    {
        if (!mrpt::system::fileExists(config_file))
        {
            throw std::runtime_error("config file '" + config_file + "' does not exist");
        }
        std::ifstream f(config_file);
        cfg.setContent(std::string(std::istreambuf_iterator<char>(f), {}));
    }
    applyConfigOverrides(cfg, sets);
}

}  // namespace emslam::apps
