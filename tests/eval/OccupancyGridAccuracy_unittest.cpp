// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/eval/OccupancyGridAccuracy.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using emslam::eval::OccupancyGridAccuracy;
using mrpt::maps::COccupancyGridMap2D;

namespace
{
/** A free 4 x 4 m grid of `cell` m cells starting at (x0, 0). */
COccupancyGridMap2D freeGrid(float x0, float cell = 0.1F)
{
    COccupancyGridMap2D g;
    g.setSize(x0, x0 + 4.0F, 0.0F, 4.0F, cell, 1.0F);  // cells hold P(free)
    return g;
}

void occupy(COccupancyGridMap2D& g, double x, double y)
{
    g.setCell(g.x2idx(x), g.y2idx(y), 0.0F);
}
}  // namespace

TEST(OccupancyGridAccuracy, countsOccupiedCellsWithinOneCell)
{
    // Truth: a wall of 20 cells along x at y = 1.05.
    COccupancyGridMap2D truth = freeGrid(0.0F);
    for (int i = 0; i < 20; ++i)
    {
        occupy(truth, 0.05 + 0.1 * i, 1.05);
    }
    // Estimate (a grid with another origin): 10 of them in place, 6 one
    // cell off (y = 1.15), 4 missing, and 4 cells where nothing is.
    COccupancyGridMap2D est = freeGrid(-1.0F);
    for (int i = 0; i < 10; ++i)
    {
        occupy(est, 0.05 + 0.1 * i, 1.05);
    }
    for (int i = 10; i < 16; ++i)
    {
        occupy(est, 0.05 + 0.1 * i, 1.15);
    }
    for (int i = 0; i < 4; ++i)
    {
        occupy(est, -0.55, 2.05 + 0.1 * i);
    }
    const auto a = OccupancyGridAccuracy::compute(est, truth);
    EXPECT_EQ(a.tolerance_cells, 1);
    EXPECT_EQ(a.estimated_occupied, 20U);
    EXPECT_EQ(a.true_occupied, 20U);
    EXPECT_EQ(a.estimated_matched, 16U);
    // Truth cells 0..16 have an estimated cell within one (cell 16 touches
    // the displaced cell 15 diagonally).
    EXPECT_EQ(a.true_matched, 17U);
    EXPECT_DOUBLE_EQ(a.precision, 0.8);
    EXPECT_DOUBLE_EQ(a.recall, 0.85);
    EXPECT_NEAR(a.f1, 2 * 0.8 * 0.85 / 1.65, 1e-12);

    // Exact: the displaced cells no longer count.
    const auto exact = OccupancyGridAccuracy::compute(est, truth, 0);
    EXPECT_DOUBLE_EQ(exact.precision, 0.5);
    EXPECT_DOUBLE_EQ(exact.recall, 0.5);
    EXPECT_DOUBLE_EQ(exact.f1, 0.5);
}

TEST(OccupancyGridAccuracy, identicalGridsScoreOneAndEmptyOnesNothing)
{
    COccupancyGridMap2D truth = freeGrid(0.0F);
    occupy(truth, 2.05, 2.05);
    const auto same = OccupancyGridAccuracy::compute(truth, truth, 0);
    EXPECT_DOUBLE_EQ(same.f1, 1.0);
    const auto none = OccupancyGridAccuracy::compute(freeGrid(0.0F), truth);
    EXPECT_EQ(none.estimated_occupied, 0U);
    EXPECT_TRUE(std::isnan(none.precision));
    EXPECT_DOUBLE_EQ(none.recall, 0.0);
    EXPECT_TRUE(std::isnan(none.f1));
    // Occupied cells on both sides, none near another: 0, not 0 / 0.
    COccupancyGridMap2D far = freeGrid(0.0F);
    occupy(far, 0.55, 0.55);
    const auto apart = OccupancyGridAccuracy::compute(far, truth);
    EXPECT_DOUBLE_EQ(apart.precision, 0.0);
    EXPECT_DOUBLE_EQ(apart.recall, 0.0);
    EXPECT_DOUBLE_EQ(apart.f1, 0.0);
}

TEST(OccupancyGridAccuracy, refusesOtherCellSizesAndNegativeTolerances)
{
    EXPECT_THROW(
        OccupancyGridAccuracy::compute(freeGrid(0.0F, 0.05F), freeGrid(0.0F)),
        std::invalid_argument);
    EXPECT_THROW(
        OccupancyGridAccuracy::compute(freeGrid(0.0F), freeGrid(0.0F), -1), std::invalid_argument);
}
