// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <atomic>
#include <cstdlib>
#include <cstring>

/** \file
 * One portable build, wide vectors where the CPU has them. A hot loop is
 * compiled twice from one body: once for the x86-64 baseline and once with
 * EMSLAM_TARGET_AVX2 (GCC's target attribute), and util::avx2Enabled()
 * picks one at run time. AVX2 alone enables no fused multiply-add, so the
 * two compilations of floating-point code round alike: both give the same
 * bits (tests check it).
 *
 * EMSLAM_SIMD=baseline in the environment (read once) or
 * util::setBaselineOnly(true) keeps every loop on the baseline, e.g. to
 * compare the two on one machine (doc/performance.md). */
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
/** 1 where x86 kernels (SSE2, and AVX2 behind EMSLAM_TARGET_AVX2) compile. */
#define EMSLAM_HAVE_AVX2_PATHS 1
/** Compiles the function it precedes for AVX2 (without FMA). */
#define EMSLAM_TARGET_AVX2 __attribute__((target("avx2")))
#else
/** 0: no x86 kernels here, every loop takes its portable path. */
#define EMSLAM_HAVE_AVX2_PATHS 0
/** Empty: no AVX2 compilation here. */
#define EMSLAM_TARGET_AVX2
#endif

namespace emslam::util
{
namespace detail
{
/** 1: AVX2 paths allowed, 0: baseline only, -1: not decided yet. */
inline std::atomic<int>& simdChoice()
{
    static std::atomic<int> choice{-1};
    return choice;
}

/** Whether this CPU runs AVX2 instructions. */
inline bool cpuHasAvx2()
{
#if EMSLAM_HAVE_AVX2_PATHS
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2");
#else
    return false;
#endif
}
}  // namespace detail

/** Whether the AVX2 compilation of a loop may run: the CPU has AVX2 and
 * neither EMSLAM_SIMD=baseline nor setBaselineOnly(true) says otherwise. */
inline bool avx2Enabled()
{
    int c = detail::simdChoice().load(std::memory_order_relaxed);
    if (c < 0)
    {
        const char* env = std::getenv("EMSLAM_SIMD");
        const bool baseline = env != nullptr && std::strcmp(env, "baseline") == 0;
        c = !baseline && detail::cpuHasAvx2() ? 1 : 0;
        detail::simdChoice().store(c, std::memory_order_relaxed);
    }
    return c == 1;
}

/** Keep every dispatched loop on its baseline compilation (true), or let the
 * environment and the CPU decide again (false). For tests and benchmarks; not meant to change
 * while loops run on other threads. */
inline void setBaselineOnly(bool baseline_only)
{
    detail::simdChoice().store(baseline_only ? 0 : -1, std::memory_order_relaxed);
}
}  // namespace emslam::util
