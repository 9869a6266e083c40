#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Runs the tests: every test of ./build (scripts/setup.sh built it), the
# installed package (scripts/check-install.sh), then the unit tests again
# under AddressSanitizer (with leak detection) and
# UndefinedBehaviorSanitizer, built into ./build-asan (libraries and unit
# tests only; see doc/reliability.md). Stops at the first failing step.
set -euo pipefail
cd "$(dirname "$0")/.."

ctest --test-dir build --output-on-failure -j2

# The installed package: find_package(emslam), the examples, the stock
# rawlog-grabber with the installed plugin, the .deb (scripts/check-install.sh).
./scripts/check-install.sh

launcher=()
if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
# -O1: sanitized code at a fraction of -O2's build time, still fast enough.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" "${launcher[@]}" \
    -DEMSLAM_SANITIZE=address,undefined -DEMSLAM_BUILD_APPS=OFF \
    -DEMSLAM_BUILD_BENCHMARKS=OFF -DEMSLAM_TSAN_TEST=OFF
cmake --build build-asan -j"$(nproc)"
ctest --test-dir build-asan -L unit --output-on-failure -j2
