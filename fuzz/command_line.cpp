// SPDX-License-Identifier: BSD-3-Clause
// The apps' command-line parser: parseCommandLine() (with deprecated
// spellings), countOption() and the --set overrides, on an argument list made
// of the input's lines, with the kinds of arguments the apps declare.
#include "FuzzFile.h"

#include <emslam/apps/CommandLine.h>
#include <emslam/io/TrajectoryFormat.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto text = emslam::fuzz::asText(data, size);
    std::vector<std::string> args{"emslam-fuzz"};
    std::size_t start = 0;
    while (start < text.size() && args.size() < 64)
    {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        args.emplace_back(text.substr(start, end - start));
        start = end + 1;
    }
    std::vector<const char*> argv;
    for (const auto& a : args)
    {
        argv.push_back(a.c_str());
    }
    try
    {
        TCLAP::CmdLine cmd("fuzzed command line", ' ', "0.0");
        TCLAP::UnlabeledValueArg<std::string> input("input", "Input", true, "", "IN", cmd);
        TCLAP::ValueArg<std::string> out("o", "out", "Output", true, "", "DIR", cmd);
        TCLAP::ValueArg<std::string> gt("", "gt", "Ground truth", false, "", "FILE", cmd);
        TCLAP::ValueArg<std::string> gt_format(
            "", "gt-format", "Format", false, "auto", "auto|tum|kitti|euroc", cmd);
        TCLAP::MultiArg<std::string> sets("", "set", "Override", false, "S.k=v", cmd);
        TCLAP::ValueArg<long long> count("", "max-frames", "Count", false, 0, "N", cmd);
        TCLAP::ValueArg<double> scale("", "scale", "Number", false, 1.0, "X", cmd);
        TCLAP::SwitchArg quiet("q", "quiet", "Switch", cmd);
        const std::vector<emslam::apps::DeprecatedSpelling> deprecated{
            {"--rawlog", "", 0, "IN"}, {"--poses", "--gt", 0, "FILE"}};
        if (!emslam::apps::parseCommandLine(
                cmd, "emslam-fuzz", static_cast<int>(argv.size()), argv.data(), deprecated))
        {
            return 0;
        }
        emslam::apps::countOption(count.getValue(), "--max-frames", 0, "emslam-fuzz");
        emslam::io::parseTrajectoryFormat(gt_format.getValue());
        mrpt::config::CConfigFileMemory cfg;
        emslam::apps::applyConfigOverrides(cfg, sets.getValue());
    }
    catch (const std::exception&)
    {
        // A clean error is the expected outcome of bad arguments.
    }
    return 0;
}
