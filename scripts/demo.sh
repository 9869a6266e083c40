#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The main job on a default input that needs no download.
# Until the mapper exists it (1) runs the stereo front-end on the Middlebury
# "Aloe" pair that Debian's opencv-doc package ships (rectified, with
# ground-truth disparities) and (2) renders a simulated stereo sequence and
# runs the paper's egomotion on it, reporting the error against the truth.
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
echo "demo: Aloe outputs in out/demo/ (disparity image, PLY cloud, rawlog for RawLogViewer)"

# Egomotion (paper §2.1) on a simulated sequence with exact ground truth:
# the first 200 frames of the 3DOF double loop around a hall.
./build/apps/emslam-sim config/sim/hall_double_loop.ini --frames 200 --seed 1 \
    -o out/demo/hall.rawlog --gt-out out/demo/hall_gt.tum
./build/apps/emslam-odometry --rawlog out/demo/hall.rawlog -o out/demo/hall_odometry.tum -q
# End-point error of the odometry against the simulator's ground truth.
paste -d' ' <(tail -n 1 out/demo/hall_gt.tum) <(tail -n 1 out/demo/hall_odometry.tum) | awk '{
    dx = $2 - $10; dy = $3 - $11; dz = $4 - $12
    printf "demo: odometry end-point error after 200 simulated frames: %.3f m\n", sqrt(dx*dx + dy*dy + dz*dz) }'
echo "demo: outputs in out/demo/ (open hall.rawlog with RawLogViewer)"
