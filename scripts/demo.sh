#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The main job on a default input that needs no download.
# Until the simulator and the mapper exist, this runs the stereo front-end on
# the Middlebury "Aloe" pair that Debian's opencv-doc package ships (rectified,
# with ground-truth disparities) and prints what it found.
set -euo pipefail
cd "$(dirname "$0")/.."

data=/usr/share/doc/opencv-doc/examples/data
for f in aloeL.jpg aloeR.jpg aloeGT.png; do
    if [ ! -f "$data/$f" ]; then
        echo "demo: $data/$f is missing: install the opencv-doc package (scripts/install-deps.sh)" >&2
        exit 1
    fi
done
mkdir -p out/demo
./build/apps/emslam-stereo \
    --left "$data/aloeL.jpg" --right "$data/aloeR.jpg" \
    --calib share/emslam/calib/middlebury-aloe.ini \
    --config config/stereo/middlebury-aloe.ini \
    --gt-disparity "$data/aloeGT.png" \
    --disparity-png out/demo/aloe_disparity.png \
    --ply out/demo/aloe_points.ply \
    --out-rawlog out/demo/aloe_frame.rawlog
echo "demo: outputs in out/demo/ (disparity image, PLY cloud, rawlog for RawLogViewer)"
