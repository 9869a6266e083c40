// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/registerAllClasses.h>

#include <gtest/gtest.h>

int main(int argc, char** argv)
{
    ::testing::InitGoogleTest(&argc, argv);
    emslam::apps::registerAllClasses();
    return RUN_ALL_TESTS();
}
