// SPDX-License-Identifier: BSD-3-Clause
// Shared helpers of the sim tests.
#include "SimTestWorlds.h"

#include "TestData.h"

#include <algorithm>
#include <filesystem>

namespace emslam::test
{
std::vector<std::string> shippedSimWorlds()
{
    std::vector<std::string> v;
    for (const auto& e : std::filesystem::directory_iterator(sourceDir() + "/config/sim"))
    {
        if (e.path().extension() == ".ini")
        {
            v.push_back(e.path().string());
        }
    }
    std::sort(v.begin(), v.end());
    return v;
}

std::string tinyWorldIni(const std::string& extra)
{
    return "[Simulation]\nfps = 5\n"
           "[Camera]\nwidth = 160\nheight = 120\nfocal_px = 100\nbaseline = 0.1\n"
           "[Trajectory]\ntype = robot3dof\nwaypoints = 3 3; 3 9\nspeed = 0.5\n"
           "camera_height = 1.0\n"
           "[World]\ntype = building\nseed = 3\n"
           "[Building]\ncell_size = 2\nmap_0 = ####/#..#/#..#/#..#/#..#/#..#/####\n" +
           extra;
}
}  // namespace emslam::test
