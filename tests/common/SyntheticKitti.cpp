// SPDX-License-Identifier: BSD-3-Clause
#include "SyntheticKitti.h"

#include "TestHelpers.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace fs = std::filesystem;

namespace emslam::test
{
std::string kittiFrameName(const std::string& dir, const char* sub, int i)
{
    char name[16];
    std::snprintf(name, sizeof(name), "%06d.png", i);
    return dir + "/" + sub + "/" + name;
}

std::uint8_t kittiPixel(int i, int side, int u, int v)
{
    return static_cast<std::uint8_t>((7 * u + 3 * v + 11 * i + 50 * side) % 256);
}

std::string writeKittiSequence(const std::string& root, int n)
{
    std::string dir = root + "/seq";
    fs::create_directories(dir + "/image_0");
    fs::create_directories(dir + "/image_1");
    char p0[256], p1[256];
    std::snprintf(
        p0, sizeof(p0), "P0: %g 0 %g 0 0 %g %g 0 0 0 1 0\n", KITTI_FX, KITTI_W / 2.0, KITTI_FX,
        KITTI_H / 2.0);
    std::snprintf(
        p1, sizeof(p1), "P1: %g 0 %g %g 0 %g %g 0 0 0 1 0\n", KITTI_FX, KITTI_W / 2.0,
        -KITTI_BASELINE * KITTI_FX, KITTI_FX, KITTI_H / 2.0);
    writeFile(dir + "/calib.txt", std::string(p0) + p1 + "P2: 1 0 0 0 0 1 0 0 0 0 1 0\n");
    std::string times, poses;
    for (int i = 0; i < n; i++)
    {
        times += std::to_string(0.1 * i) + "\n";
        const double a = 0.01 * i;
        char line[256];
        std::snprintf(
            line, sizeof(line), "%.9f 0 %.9f 0 0 1 0 0 %.9f 0 %.9f %d\n", std::cos(a), std::sin(a),
            -std::sin(a), std::cos(a), i);
        poses += line;
        for (int side = 0; side < 2; side++)
        {
            cv::Mat im(KITTI_H, KITTI_W, CV_8UC1);
            for (int v = 0; v < KITTI_H; v++)
            {
                for (int u = 0; u < KITTI_W; u++)
                {
                    im.at<std::uint8_t>(v, u) = kittiPixel(i, side, u, v);
                }
            }
            cv::imwrite(kittiFrameName(dir, side == 0 ? "image_0" : "image_1", i), im);
        }
    }
    writeFile(dir + "/times.txt", times);
    writeFile(root + "/poses.txt", poses);
    return dir;
}

}  // namespace emslam::test
