// SPDX-License-Identifier: BSD-3-Clause
// emslam-odometry: stereo visual odometry (egomotion only) over a rawlog.
// See doc/apps/emslam-odometry.md.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/OdometryApp.h>

int main(int argc, char** argv)
{
    return emslam::apps::appMain<emslam::apps::OdometryApp>("emslam-odometry", argc, argv);
}
