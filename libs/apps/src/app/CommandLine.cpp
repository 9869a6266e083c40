// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ConfigValidation.h>
#include <emslam/io/IniFile.h>
#include <emslam/slam/ConfigRenames.h>

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
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
        const std::string missing = missingRequired(c);
        if (!missing.empty())
        {
            throw std::invalid_argument(
                "missing " + missing + "; try " + c.getProgramName() + " --help");
        }
        // TCLAP's argId() is blank when no single argument is to blame.
        const bool has_id = e.argId().find_first_not_of(' ') != std::string::npos;
        throw std::invalid_argument(
            "bad command line: " + e.error() + (has_id ? " (" + e.argId() + ")" : "") + "; try " +
            c.getProgramName() + " --help");
    }

private:
    /** "required argument X" / "required arguments X, Y" for the required
     * arguments not given, or "". */
    static std::string missingRequired(TCLAP::CmdLineInterface& c)
    {
        std::vector<std::string> names;
        for (const TCLAP::Arg* a : c.getArgList())
        {
            if (a->isRequired() && !a->isSet())
            {
                // Unlabeled: "<CONFIG.ini>"; labeled: "--out <DIR>".
                const std::string id = a->shortID();
                const auto space = id.find(' ');
                names.push_back(
                    id.rfind('<', 0) == 0
                        ? id
                        : "--" + a->getName() +
                              (space == std::string::npos ? "" : id.substr(space)));
            }
        }
        std::string out;
        for (const auto& n : names)
        {
            out += (out.empty() ? "" : ", ") + n;
        }
        return names.empty()       ? ""
               : names.size() == 1 ? "required argument " + out
                                   : "required arguments " + out;
    }
};

/** The value of `--flag=value`, or nullopt when `arg` is not that flag. */
std::optional<std::string> inlineValue(const std::string& arg, const std::string& flag)
{
    if (arg.size() > flag.size() && arg.compare(0, flag.size(), flag) == 0 &&
        arg[flag.size()] == '=')
    {
        return arg.substr(flag.size() + 1);
    }
    return std::nullopt;
}

/** The argument of `cmd` spelled `word` ("--name" or "-f"), or nullptr. */
const TCLAP::Arg* findOption(TCLAP::CmdLine& cmd, const std::string& word)
{
    for (const TCLAP::Arg* a : cmd.getArgList())
    {
        if ((!a->getName().empty() && word == "--" + a->getName()) ||
            (!a->getFlag().empty() && word == "-" + a->getFlag()))
        {
            return a;
        }
    }
    return nullptr;
}

/** True for "-5", "-.5": a negative number given as a value, not an option. */
bool isNegativeNumber(const std::string& word)
{
    return word.size() > 1 && word[0] == '-' &&
           (std::isdigit(static_cast<unsigned char>(word[1])) || word[1] == '.');
}

/** True for "-qv": single-letter switches of `cmd` written together. */
bool isCombinedSwitches(TCLAP::CmdLine& cmd, const std::string& word)
{
    if (word.size() < 3 || word[1] == '-')
    {
        return false;
    }
    for (std::size_t i = 1; i < word.size(); ++i)
    {
        const TCLAP::Arg* a = findOption(cmd, std::string("-") + word[i]);
        if (a == nullptr || a->isValueRequired())
        {
            return false;
        }
    }
    return true;
}
}  // namespace

std::vector<std::string> requireKnownOptions(
    TCLAP::CmdLine& cmd, const std::string& program, const std::vector<std::string>& args)
{
    std::vector<std::string> out;
    for (std::size_t i = 0; i < args.size(); ++i)
    {
        const std::string& word = args[i];
        if (word == "--")
        {
            out.insert(out.end(), args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
            break;
        }
        if (word.size() < 2 || word[0] != '-' || isNegativeNumber(word))
        {
            out.push_back(word);
            continue;
        }
        const auto eq = word.find('=');
        const std::string name = word.substr(0, eq);
        const TCLAP::Arg* a = findOption(cmd, name);
        if (a == nullptr && eq == std::string::npos && isCombinedSwitches(cmd, word))
        {
            out.push_back(word);
            continue;
        }
        if (a == nullptr)
        {
            throw std::invalid_argument(
                "unknown option '" + name + "'; try " + program + " --help");
        }
        out.push_back(name);
        if (eq != std::string::npos)
        {
            if (!a->isValueRequired())
            {
                throw std::invalid_argument(
                    name + " takes no value (got '" + word + "'); try " + program + " --help");
            }
            out.push_back(word.substr(eq + 1));  // --name=value, as GNU tools take it
        }
        else if (a->isValueRequired() && i + 1 < args.size())
        {
            out.push_back(args[++i]);  // its value, whatever it looks like
        }
    }
    return out;
}

std::vector<std::string> rewriteDeprecatedSpellings(
    const std::string& program,
    const std::vector<std::string>& args,
    const std::vector<DeprecatedSpelling>& deprecated)
{
    std::map<std::size_t, std::string> positional;
    std::vector<std::string> out;
    for (std::size_t i = 0; i < args.size(); ++i)
    {
        const DeprecatedSpelling* match = nullptr;
        std::optional<std::string> value;
        for (const auto& d : deprecated)
        {
            if (args[i] == d.old_flag || (value = inlineValue(args[i], d.old_flag)))
            {
                match = &d;
                break;
            }
        }
        if (!match)
        {
            out.push_back(args[i]);
            continue;
        }
        if (!value)
        {
            if (i + 1 >= args.size())
            {
                throw std::invalid_argument(
                    match->old_flag + " needs a value; try " + program + " --help");
            }
            value = args[++i];
        }
        std::fprintf(
            stderr,
            "%s: warning: %s is deprecated and goes away in the next release; give %s instead\n",
            program.c_str(), match->old_flag.c_str(),
            (match->new_flag.empty() ? match->new_name + " as positional argument " +
                                           std::to_string(match->position + 1)
                                     : match->new_flag + " " + match->new_name)
                .c_str());
        if (!match->new_flag.empty())
        {
            out.push_back(match->new_flag);
            out.push_back(*value);
        }
        else if (!positional.emplace(match->position, *value).second)
        {
            throw std::invalid_argument(
                "positional argument " + std::to_string(match->position + 1) + " given twice (" +
                match->old_flag + "); try " + program + " --help");
        }
    }
    // The old flags' values lead, so they must fill the first positions.
    std::size_t expected = 0;
    for (const auto& [position, value] : positional)
    {
        if (position != expected++)
        {
            throw std::invalid_argument(
                "give every input positionally (the deprecated flags cannot be mixed with "
                "positional inputs); try " +
                program + " --help");
        }
    }
    std::vector<std::string> rewritten;
    for (const auto& [position, value] : positional)
    {
        rewritten.push_back(value);
    }
    rewritten.insert(rewritten.end(), out.begin(), out.end());
    return rewritten;
}

bool parseCommandLine(
    TCLAP::CmdLine& cmd,
    const char* program,
    int argc,
    const char** argv,
    const std::vector<DeprecatedSpelling>& deprecated)
{
    const std::vector<std::string> given(argv + std::min(argc, 1), argv + std::max(argc, 0));
    std::vector<std::string> args =
        requireKnownOptions(cmd, program, rewriteDeprecatedSpellings(program, given, deprecated));
    args.insert(args.begin(), program);
    ThrowingOutput out;
    // setOutput() does not free the default output object; take it over.
    const std::unique_ptr<TCLAP::CmdLineOutput> default_output(cmd.getOutput());
    cmd.setOutput(&out);
    std::vector<const char*> c_args;
    for (const auto& a : args)
    {
        c_args.push_back(a.c_str());
    }
    const bool run = cmd.parse(static_cast<int>(c_args.size()), c_args.data());
    cmd.setOutput(nullptr);
    return run;
}

void usageError(const std::string& program, const std::string& message)
{
    throw std::invalid_argument("bad command line: " + message + "; try " + program + " --help");
}

std::string withDefault(const std::string& description, const std::string& value)
{
    return description + " (default: " + value + ")";
}

std::size_t countOption(
    long long value, const std::string& flag, long long min, const std::string& program)
{
    if (value < min)
    {
        throw std::invalid_argument(
            flag + " must be at least " + std::to_string(min) + " (got " + std::to_string(value) +
            "); try " + program + " --help");
    }
    return static_cast<std::size_t>(value);
}

void requireValidOverrides(
    const std::vector<std::string>& sets, const mrpt::config::CConfigFileBase& reference)
{
    mrpt::config::CConfigFileMemory given;
    applyConfigOverrides(given, sets);
    std::ostringstream renamed;  // loadConfig() warns
    try
    {
        requireValidConfig(
            util::withCurrentNames(given, slam::configRenames(), renamed), reference);
    }
    catch (const std::invalid_argument& e)
    {
        throw std::invalid_argument(std::string("--set: ") + e.what());
    }
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
    // Old section and key names are read under the new ones, the file and
    // the overrides each on their own: an old name in --set still wins.
    mrpt::config::CConfigFileMemory file;
    if (!config_file.empty())
    {
        file.setContent(io::readIniFile(config_file, "config file"));
    }
    cfg.setContent(util::withCurrentNames(file, slam::configRenames(), std::cerr).getContent());
    mrpt::config::CConfigFileMemory given;
    applyConfigOverrides(given, sets);
    const auto overrides = util::withCurrentNames(given, slam::configRenames(), std::cerr);
    std::vector<std::string> sections;
    overrides.getAllSections(sections);
    for (const auto& section : sections)
    {
        std::vector<std::string> keys;
        overrides.getAllKeys(section, keys);
        for (const auto& key : keys)
        {
            cfg.write(section, key, overrides.read_string(section, key, {}));
        }
    }
}

}  // namespace emslam::apps
