// SPDX-License-Identifier: BSD-3-Clause
// emslam-import: KITTI / EuRoC / TUM RGB-D sequence -> rawlog (+ TUM ground truth).
// See doc/apps/emslam-import.md.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/ImportApp.h>

int main(int argc, char** argv)
{
    return emslam::apps::appMain<emslam::apps::ImportApp>("emslam-import", argc, argv);
}
