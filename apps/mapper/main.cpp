// SPDX-License-Identifier: BSD-3-Clause
// emslam-mapper: Entropy Minimization SLAM over a rawlog (the main job).
// See doc/apps/emslam-mapper.md.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/MapperApp.h>

int main(int argc, char** argv)
{
    return emslam::apps::appMain<emslam::apps::MapperApp>("emslam-mapper", argc, argv);
}
