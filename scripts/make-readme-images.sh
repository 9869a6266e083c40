#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Regenerates the README's floor plan from a fresh run of the default demo
# (scripts/demo.sh: the simulated hall double loop): map_top.png as the mapper
# writes it. The README's 3D view is a window capture (see the README).
#   scripts/make-readme-images.sh           # runs the demo first (~3 min idle)
#   scripts/make-readme-images.sh --reuse   # takes the last demo run in out/demo
set -euo pipefail
cd "$(dirname "$0")/.."

if [[ "${1:-}" != "--reuse" ]]; then
    ./scripts/demo.sh
fi
map=out/demo/hall_map
[[ -f "$map/map_top.png" ]] ||
    { echo "make-readme-images: '$map/map_top.png' missing: run scripts/demo.sh" >&2; exit 1; }
cp "$map/map_top.png" doc/images/map_top_hall.png
echo "make-readme-images: wrote doc/images/map_top_hall.png"
