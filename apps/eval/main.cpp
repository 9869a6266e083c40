// SPDX-License-Identifier: BSD-3-Clause
// emslam-eval: an estimated trajectory against ground truth (ATE, KITTI drift,
// loop gap). See doc/apps/emslam-eval.md.
#include <emslam/apps/AppMain.h>
#include <emslam/apps/EvalApp.h>

int main(int argc, char** argv)
{
    return emslam::apps::appMain<emslam::apps::EvalApp>("emslam-eval", argc, argv);
}
