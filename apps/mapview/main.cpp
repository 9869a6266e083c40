// SPDX-License-Identifier: BSD-3-Clause
// emslam-mapview: opens entropy_map.bin (or a .3Dscene) in a 3D window.
// See doc/apps/emslam-mapview.md.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/MapViewApp.h>

int main(int argc, char** argv)
{
    return emslam::apps::appMain<emslam::apps::MapViewApp>("emslam-mapview", argc, argv);
}
