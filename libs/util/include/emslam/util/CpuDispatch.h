// SPDX-License-Identifier: BSD-3-Clause
#pragma once

/** \file
 * EMSLAM_CLONE_AVX2 before a function compiles it twice, for AVX2 and for the
 * x86-64 baseline, and the loader picks the one the CPU runs (GCC's
 * `target_clones`): one portable build, wide vectors where they exist. AVX2
 * alone enables no fused multiply-add, so a clone of floating-point code
 * rounds as the baseline does: both give the same bits.
 *
 * Empty with other compilers and under the sanitizers: the clones resolve
 * through an ifunc that runs before the sanitizers' runtime is up
 * (ThreadSanitizer crashes at start-up). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(__SANITIZE_THREAD__) && !defined(__SANITIZE_ADDRESS__)
#define EMSLAM_CLONE_AVX2 __attribute__((target_clones("avx2", "default")))
#else
#define EMSLAM_CLONE_AVX2
#endif
