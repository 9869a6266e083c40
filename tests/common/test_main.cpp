// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"

#include <emslam/hwdrivers/registerAllClasses.h>
#include <emslam/sim/registerAllClasses.h>
#include <emslam/slam/registerAllClasses.h>

#include <gtest/gtest.h>

#include <cstdlib>

namespace
{
/** The temporary folders of passed tests are removed at the end; a failed
 * test's stay (with every other of its process) for a look. */
class TempDirCleanup : public ::testing::Environment
{
public:
    void TearDown() override
    {
        if (::testing::UnitTest::GetInstance()->Passed() &&
            std::getenv("EMSLAM_KEEP_TEST_DIRS") == nullptr)
        {
            emslam::test::removeTempDirs();
        }
    }
};
}  // namespace

int main(int argc, char** argv)
{
    ::testing::InitGoogleTest(&argc, argv);
    ::testing::AddGlobalTestEnvironment(new TempDirCleanup);
    // Every library's classes (the suites read rawlogs of all of them).
    emslam::slam::registerAllClasses();
    emslam::sim::registerAllClasses();
    emslam::hwdrivers::registerAllClasses();
    return RUN_ALL_TESTS();
}
