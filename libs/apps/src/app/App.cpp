// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/App.h>

#include <stdexcept>

namespace emslam::apps
{
void App::initialize(int argc, const char** argv)
{
    m_help_requested = !parseArguments(argc, argv);
}

void App::run()
{
    if (!m_help_requested)
    {
        execute();
    }
}

bool App::parseCommandLine(
    TCLAP::CmdLine& cmd,
    int argc,
    const char** argv,
    const std::vector<DeprecatedSpelling>& deprecated)
{
    if (!emslam::apps::parseCommandLine(cmd, m_program, argc, argv, deprecated))
    {
        return false;
    }
    if (m_max_frames_arg)
    {
        m_max_frames = countOption(m_max_frames_arg->getValue(), "--max-frames", 0, m_program);
    }
    m_quiet = m_quiet_arg && m_quiet_arg->getValue();
    return true;
}

void App::addSetOption(TCLAP::CmdLine& cmd, const std::string& help)
{
    m_set_arg = std::make_unique<TCLAP::MultiArg<std::string>>(
        "", "set", help, false, "SECTION.key=value", cmd);
}

void App::addMaxFramesOption(TCLAP::CmdLine& cmd, const std::string& help)
{
    m_max_frames_arg = std::make_unique<TCLAP::ValueArg<long long>>(
        "", "max-frames", withDefault(help, "0"), false, 0, "N", cmd);
}

void App::addQuietOption(TCLAP::CmdLine& cmd, const std::string& help)
{
    m_quiet_arg = std::make_unique<TCLAP::SwitchArg>("q", "quiet", help, cmd);
}

const std::vector<std::string>& App::overrides() const
{
    static const std::vector<std::string> none;
    return m_set_arg ? m_set_arg->getValue() : none;
}

void App::loadParameters(const std::string& config_file, const mrpt::config::CConfigFileBase* known)
{
    loadConfig(params, config_file, overrides());
    if (known != nullptr)
    {
        // A typo or a non-number must not run silently on a default.
        requireValidOverrides(overrides(), *known);
    }
}

void App::usageError(const std::string& message) const
{
    emslam::apps::usageError(m_program, message);
}

}  // namespace emslam::apps
