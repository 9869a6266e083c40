#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The main job on a default input that needs no download: the simulator
# renders the paper's hall double loop (a 3DOF robot, exact ground truth),
# emslam-mapper maps it (egomotion + global rectification, Exp. 11), and
# emslam-eval measures egomotion and SLAM against the truth.
set -euo pipefail
cd "$(dirname "$0")/.."

out=out/demo
mkdir -p "$out"
./build/apps/emslam-sim config/sim/hall_double_loop.ini --seed 1 \
    -o "$out/hall.rawlog" --gt-out "$out/hall_gt.tum"
./build/apps/emslam-mapper config/mapper/3dof-low-structured.ini "$out/hall.rawlog" \
    --out "$out/hall_map" --gt "$out/hall_gt.tum"
for t in egomotion slam; do
    ./build/apps/emslam-eval "$out/hall_gt.tum" "$out/hall_map/trajectory_$t.tum" \
        --json "$out/hall_map/eval_$t.json" >/dev/null
done

# The loop closes in truth: the first and last poses coincide.
value() { sed -n "s/.*\"$1\": \([-0-9.e]*\).*/\1/p" "$2" | head -n 1; }
printf 'demo: hall double loop, %s m, %s frames\n' \
    "$(value path_length_m "$out/hall_map/eval_slam.json")" \
    "$(value frames "$out/hall_map/summary.json")"
for t in egomotion slam; do
    printf 'demo: %-9s loop gap %.3f m, ATE %.3f m\n' "$t" \
        "$(value loop_gap_m "$out/hall_map/eval_$t.json")" \
        "$(value ate_rmse_m "$out/hall_map/eval_$t.json")"
done
echo "demo: report $out/hall_map/report.html; map $out/hall_map/map.3Dscene (SceneViewer3D)," \
    "map.ply, trajectories, stats.csv, summary.json"
