// SPDX-License-Identifier: BSD-3-Clause
// emslam-stereo: the stereo front-end on an image pair or a rawlog.
// See doc/apps/emslam-stereo.md.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/StereoApp.h>

int main(int argc, char** argv)
{
    return emslam::apps::appMain<emslam::apps::StereoApp>("emslam-stereo", argc, argv);
}
