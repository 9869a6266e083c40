// SPDX-License-Identifier: BSD-3-Clause
// emslam-experiments: the paper's experiments, rendered, mapped and tabulated.
// See doc/apps/emslam-experiments.md.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/ExperimentsApp.h>

int main(int argc, char** argv)
{
    return emslam::apps::appMain<emslam::apps::ExperimentsApp>("emslam-experiments", argc, argv);
}
