#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Regenerates the README's map images from a fresh run of the default demo
# (scripts/demo.sh: the simulated hall double loop): the floor plan
# map_top.png as the mapper writes it, and map.3Dscene as emslam-mapview
# draws it, off-screen (no display needed).
#   scripts/make-readme-images.sh           # runs the demo first (~3 min idle)
#   scripts/make-readme-images.sh --reuse   # takes the last demo run in out/demo
set -euo pipefail
cd "$(dirname "$0")/.."

if [[ "${1:-}" != "--reuse" ]]; then
    ./scripts/demo.sh
fi
map=out/demo/hall_map
for f in "$map/map_top.png" "$map/map.3Dscene"; do
    [[ -f "$f" ]] || { echo "make-readme-images: '$f' missing: run scripts/demo.sh" >&2; exit 1; }
done
cp "$map/map_top.png" doc/images/map_top_hall.png
./build/apps/emslam-mapview "$map/map.3Dscene" --screenshot doc/images/map_scene_hall.png
echo "make-readme-images: wrote doc/images/map_top_hall.png and doc/images/map_scene_hall.png"
