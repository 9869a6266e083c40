#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# One-command set-up: installs the Debian dependencies, builds emslam in
# Release mode into ./build, and runs the main job on an input that needs no
# download. Safe to re-run (apt and CMake only redo what changed).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
bash scripts/demo.sh
