// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"

#include <emslam/apps/EnergyScanOutputs.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace
{
using emslam::rectify::EnergyScanLine;

std::string readText(const std::string& file)
{
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/** Two lines of a 60-element scan: a translation with 2 steps a side, a
 * rotation with 1. */
emslam::apps::MapperEnergyScan twoLines()
{
    emslam::apps::MapperEnergyScan m;
    auto& s = m.scan;
    EnergyScanLine t;
    t.action = 30;
    t.dimension = 2;
    t.offsets = {-0.1, -0.05, 0.0, 0.05, 0.1};
    t.energies = {10.5, 10.25, 10.0, 10.125, 10.0};
    t.energy_at_truth = 10.0;
    t.argmin_offset = 0.0;  // a tie with +0.1: the nearest to 0 wins
    t.min_energy = 10.0;
    t.curvature = (10.125 + 10.25 - 20.0) / 0.0025;
    t.slope = (10.125 - 10.25) / 0.1;
    EnergyScanLine r;
    r.action = 1;
    r.dimension = 4;
    r.offsets = {-mrpt::DEG2RAD(2.0), 0.0, mrpt::DEG2RAD(2.0)};
    r.energies = {9.75, 10.0, 10.5};
    r.energy_at_truth = 10.0;
    r.argmin_offset = -mrpt::DEG2RAD(2.0);
    r.min_energy = 9.75;
    r.curvature = 0.25 / (r.offsets[2] * r.offsets[2]);
    r.slope = 0.75 / (2 * r.offsets[2]);
    s.lines = {r, t};
    s.summary.lines = 2;
    s.summary.lines_at_truth = 1;
    s.summary.elements = 60;
    s.summary.evaluations = 7;
    s.summary.energy_at_truth = 10.0;
    s.summary.fraction_at_truth = 0.5;
    s.summary.median_abs_argmin_translation_m = 0.0;
    s.summary.median_abs_argmin_rotation_rad = mrpt::DEG2RAD(2.0);
    s.summary.dimensions = {{2, 1, 1.0, 0.0, t.curvature}, {4, 1, 0.0, mrpt::DEG2RAD(2.0), 0.5}};
    m.entropy_egomotion = 10.25;
    m.entropy_slam = 9.5;
    return m;
}
}  // namespace

TEST(EnergyScanOutputs, csvHasOneRowPerLineInMetresAndDegrees)
{
    const std::string file = emslam::test::makeTempDir("energy_scan_csv") + "/energy_scan.csv";
    emslam::apps::writeEnergyScanCsv(twoLines().scan, file);
    EXPECT_EQ(
        readText(file),
        "action,elements_moved,dimension,unit,step,energy_at_truth,argmin_offset,min_minus_truth,"
        "truth_is_min,curvature,slope,dE_-2,dE_-1,dE_+1,dE_+2\n"
        "1,59,theta_y,deg,2,10,-2,-0.25,0,0.0625,0.1875,,-0.25,0.5,\n"
        "30,30,z,m,0.05,10,0,0,1,150,-1.25,0.5,0.25,0.125,0\n");
}

TEST(EnergyScanOutputs, jsonHoldsTheAggregateInDegrees)
{
    const std::string j = emslam::apps::energyScanJson(twoLines());
    for (const char* part :
         {"\"lines\": 2, \"lines_at_truth\": 1, \"elements\": 60", "\"energy_at_truth\": 10,",
          "\"energy_at_egomotion\": 10.25", "\"energy_at_slam\": 9.5", "\"fraction_at_truth\": 0.5",
          "\"median_abs_argmin_translation_m\": 0,", "\"median_abs_argmin_rotation_deg\": 2,",
          "\"z\": {\"unit\": \"m\", \"lines\": 1",
          "\"theta_y\": {\"unit\": \"deg\", \"lines\": 1, \"fraction_at_truth\": 0, "
          "\"median_abs_argmin\": 2,"})
    {
        EXPECT_NE(j.find(part), std::string::npos) << part << "\n" << j;
    }
}
