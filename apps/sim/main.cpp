// SPDX-License-Identifier: BSD-3-Clause
// emslam-sim: renders a synthetic stereo world into a rawlog + ground truth.
// See doc/apps/emslam-sim.md.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/SimApp.h>

int main(int argc, char** argv)
{
    return emslam::apps::appMain<emslam::apps::SimApp>("emslam-sim", argc, argv);
}
