// SPDX-License-Identifier: BSD-3-Clause
// EuRoC cam*/sensor.yaml: EurocSensorYaml's parser and its accessors, then the
// whole calibration reader with the input as both cameras.
#include "FuzzFile.h"

#include <emslam/io/CalibrationFiles.h>
#include <emslam/io/EurocSensorYaml.h>

#include <cstddef>
#include <cstdint>
#include <exception>

namespace
{
void readKeys(const emslam::io::EurocSensorYaml& yaml)
{
    // Each accessor may throw on its own: try them one by one.
    for (const char* key : {"camera_model", "distortion_model", "rate_hz", "T_BS.cols"})
    {
        try
        {
            if (yaml.has(key) && !yaml.isMap(key) && !yaml.isList(key))
            {
                yaml.text(key);
                yaml.number(key);
            }
        }
        catch (const std::exception&)
        {
        }
    }
    for (const char* key : {"intrinsics", "distortion_coefficients", "resolution"})
    {
        try
        {
            yaml.numbers(key, {2, 4});
        }
        catch (const std::exception&)
        {
        }
    }
    try
    {
        yaml.numbers("T_BS.data", {16});
        yaml.lineOf("T_BS.data");
    }
    catch (const std::exception&)
    {
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto text = emslam::fuzz::asText(data, size);
    try
    {
        readKeys(emslam::io::EurocSensorYaml::parse(text, "sensor.yaml"));
    }
    catch (const std::exception&)
    {
        // A clean error is the expected outcome of a bad file.
    }
    const auto& folder = emslam::fuzz::FuzzFolder::instance();
    const std::string file = folder.write("sensor.yaml", text);
    try
    {
        emslam::io::loadEurocCalibration(file, file);
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
