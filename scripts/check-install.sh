#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Checks emslam as an installed package, from ./build (scripts/setup.sh built
# it): installs it to a scratch prefix; runs the installed emslam-mapper
# --help; builds examples/ against it with find_package(emslam) and runs both
# examples; records a few frames with the stock rawlog-grabber and the
# installed plugin; builds the Debian package (cpack -G DEB) and, as root on
# a machine without emslam installed, installs it with dpkg, runs
# emslam-mapper --help from PATH and removes it again.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
prefix="$scratch/prefix"

step() { printf '== check-install: %s\n' "$*"; }

step "install to a scratch prefix"
cmake --install build --prefix "$prefix" >/dev/null
"$prefix/bin/emslam-mapper" --help >/dev/null

step "examples against the installed package"
cmake -S examples -B "$scratch/examples" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$scratch/examples" -j2 >/dev/null
"$scratch/examples/entropy_map_from_ini"
# The installed world by its name: found in the prefix's share/emslam/config.
"$prefix/bin/emslam-sim" hall_double_loop --max-frames 12 -o "$scratch/hall.rawlog" -q
"$scratch/examples/map_rawlog" "$prefix/share/emslam/config/mapper/3dof-low-structured.ini" \
    "$scratch/hall.rawlog"

if command -v rawlog-grabber >/dev/null; then
    step "stock rawlog-grabber with the installed plugin"
    mkdir -p "$scratch/grab"
    cat >"$scratch/grab/grab.ini" <<INI
[global]
rawlog_prefix = grab
time_between_launches = 100
[SIM]
driver = CSimulatedStereoCamera
sensorLabel = STEREO
process_rate = 10
loop = true
world_file = $prefix/share/emslam/config/sim/hall_double_loop.ini
INI
    # The stock loop ends when its standard input does.
    (cd "$scratch/grab" && sleep 4 | rawlog-grabber grab.ini -p "$prefix/lib/libemslam_hwdrivers.so" \
        >grab.log 2>&1) || { cat "$scratch/grab/grab.log"; exit 1; }
    # rawlog-edit --info: "Sensor (Label/Occurs/...) : STEREO / 30 / ..."
    "$prefix/bin/emslam-run" rawlog-edit --info -i "$scratch"/grab/grab_*.rawlog \
        | grep -Eq "STEREO +/ +[1-9]" || { echo "no stereo frame recorded"; exit 1; }
fi

step "Debian package"
(cd build && cpack -G DEB >/dev/null)
deb=$(ls -t build/emslam_*.deb | head -n 1)
echo "built $deb"
installed() { dpkg-query -W -f='${Status}' emslam 2>/dev/null | grep -q "ok installed"; }
if [ "$(id -u)" = 0 ] && ! installed && [ "${EMSLAM_CHECK_DPKG:-1}" = 1 ]; then
    dpkg -i "$deb" >/dev/null
    emslam-mapper --help >/dev/null
    ls /usr/share/emslam/config/mapper/kitti.ini >/dev/null
    dpkg --purge emslam >/dev/null
    step "dpkg -i, emslam-mapper --help from PATH, dpkg --purge: ok"
else
    step "dpkg -i skipped (not root, emslam already installed, or EMSLAM_CHECK_DPKG=0)"
fi
cd "$root"
step "ok"
