// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/util/CpuDispatch.h>

#include <gtest/gtest.h>

#include <cstdlib>

using emslam::util::avx2Enabled;
using emslam::util::setBaselineOnly;

// The switch of the dispatched loops: forced to the baseline, back to what
// the CPU and the environment say, and the environment read again.
TEST(CpuDispatch, baselineOnlyIsObeyedAndUndone)
{
    setBaselineOnly(true);
    EXPECT_FALSE(avx2Enabled());
    setBaselineOnly(false);
    EXPECT_EQ(avx2Enabled(), emslam::util::detail::cpuHasAvx2() && !std::getenv("EMSLAM_SIMD"));

    ::setenv("EMSLAM_SIMD", "baseline", 1);
    setBaselineOnly(false);  // decide again, from the environment
    EXPECT_FALSE(avx2Enabled());
    ::unsetenv("EMSLAM_SIMD");
    setBaselineOnly(false);
    EXPECT_EQ(avx2Enabled(), emslam::util::detail::cpuHasAvx2());
}

// Only the word `baseline` turns the wide loops off; anything else leaves
// the choice to the CPU.
TEST(CpuDispatch, otherValuesLeaveTheChoiceToTheCpu)
{
    ::setenv("EMSLAM_SIMD", "avx2", 1);
    setBaselineOnly(false);
    EXPECT_EQ(avx2Enabled(), emslam::util::detail::cpuHasAvx2());
    ::unsetenv("EMSLAM_SIMD");
    setBaselineOnly(false);
}
