// SPDX-License-Identifier: BSD-3-Clause
// emslam-grabber: records stereo cameras (and stock MRPT sensors) into a rawlog.
// See doc/apps/emslam-grabber.md.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/GrabberApp.h>

int main(int argc, char** argv)
{
    return emslam::apps::appMain<emslam::apps::GrabberApp>("emslam-grabber", argc, argv);
}
