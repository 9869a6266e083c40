// SPDX-License-Identifier: BSD-3-Clause
// Test helper: a small KITTI odometry sequence written to disk.
#pragma once

#include <cstdint>
#include <string>

namespace emslam::test
{
/** Image size, focal length [px] and baseline [m] of writeKittiSequence(). */
constexpr int KITTI_W = 40;
constexpr int KITTI_H = 24;
constexpr double KITTI_FX = 50.0;
constexpr double KITTI_BASELINE = 0.25;

/** `dir/sub/NNNNNN.png`: image `i` of the camera folder `sub` ("image_0"). */
std::string kittiFrameName(const std::string& dir, const char* sub, int i);

/** Pixel (u, v) of synthetic image `i`, left (0) or right (1). */
std::uint8_t kittiPixel(int i, int side, int u, int v);

/** A small valid KITTI sequence with `n` frames in `root/seq` (returned);
 * poses in `root/poses.txt` (frame i at z = i metres, rotated i*0.01 rad
 * about y), times 0.1 s apart. */
std::string writeKittiSequence(const std::string& root, int n);

}  // namespace emslam::test
