#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs emslam's build and test dependencies from Debian 12 packages.
# Safe to re-run: apt-get only installs what is missing.
set -euo pipefail

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
    SUDO="sudo"
fi

export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
# chromium: the MapperReport test renders report.html with it, headless
# (the test is skipped without it). xvfb, xauth: the live-viewer test opens
# its window on a virtual X display (skipped without Xvfb). doxygen: the API
# reference must build without a warning (skipped without it).
# gstreamer1.0-plugins-base: the CVideoStereoCamera test reads a GStreamer
# pipeline (videotestsrc, videoconvert, appsink; skipped without it).
$SUDO apt-get install -y -q --no-install-recommends \
    build-essential cmake pkg-config ca-certificates \
    libmrpt-dev mrpt-apps mrpt-common liboctomap-dev \
    libopencv-dev opencv-doc libeigen3-dev \
    libusb-1.0-0-dev libdc1394-dev zlib1g-dev \
    libgtest-dev libgmock-dev libbenchmark-dev \
    clang-format doxygen \
    chromium \
    xvfb xauth \
    gstreamer1.0-plugins-base
