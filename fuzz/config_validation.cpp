// SPDX-License-Identifier: BSD-3-Clause
// INI files and --set overrides: the text goes into a CConfigFileMemory, the
// lines after a line "---" are `--set Section.key=value` items; then the
// apps' checks (requireValidOverrides(), requireValidConfig()) and every
// parameter struct's loadFromConfigFile() + validate() run on it.
#include "FuzzFile.h"

#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ConfigValidation.h>
#include <emslam/hwdrivers/CDigiclopsStereoCamera.h>
#include <emslam/sim/StereoRenderer.h>
#include <emslam/slam/EntropySlam.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

namespace
{
/** Every valid section and key, as the apps build their reference. */
const mrpt::config::CConfigFileMemory& reference()
{
    static const mrpt::config::CConfigFileMemory known = []
    {
        mrpt::config::CConfigFileMemory c;
        emslam::slam::EntropySlam::TParameters().saveToConfigFile(c);
        return c;
    }();
    return known;
}

std::vector<std::string> lines(std::string_view text)
{
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start < text.size())
    {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        out.emplace_back(text.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

template <typename Params>
void loadAndValidate(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    try
    {
        Params p;
        p.loadFromConfigFile(cfg, section);
        p.validate();
    }
    catch (const std::exception&)
    {
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto [ini, set_text] = emslam::fuzz::splitAtLine(emslam::fuzz::asText(data, size), "---");
    const std::vector<std::string> sets = lines(set_text);
    mrpt::config::CConfigFileMemory cfg;
    try
    {
        cfg.setContent(std::string(ini));
        emslam::apps::applyConfigOverrides(cfg, sets);
    }
    catch (const std::exception&)
    {
        // A clean error is the expected outcome of a bad file or item.
    }
    try
    {
        emslam::apps::requireValidOverrides(sets, reference());
    }
    catch (const std::exception&)
    {
    }
    try
    {
        emslam::apps::requireValidConfig(cfg, reference(), {}, true);
    }
    catch (const std::exception&)
    {
    }
    try
    {
        emslam::slam::EntropySlam::TParameters p;
        p.loadFromConfigFile(cfg);
    }
    catch (const std::exception&)
    {
    }
    loadAndValidate<emslam::sim::StereoRenderer::TParameters>(cfg, "Camera");
    loadAndValidate<emslam::hwdrivers::CDigiclopsStereoCamera::TParameters>(cfg, "DIGICLOPS");
    return 0;
}
