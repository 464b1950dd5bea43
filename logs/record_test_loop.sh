#!/usr/bin/env bash
# Regenerates logs/test_loop.lcmlog: the full 108.6 s scripted loop
# config/drives/test_loop.yaml around the ring corridor of worlds/test
# (seed 7), ODOMETRY, LIDAR_SCAN and SIM_TRUTH only. Recorded in-process by
# aslam-slam-bench (no bus, event time = simulated time): the same build
# writes the same bytes every time. Run after scripts/build
# (or set BUILD_DIR to another build folder).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
build="${BUILD_DIR:-build}"
out=logs/test_loop.lcmlog

"$build/eval/aslam-slam-bench" --world worlds/test --drive config/drives/test_loop.yaml \
  --config config/aslam.yaml --seed 7 --noslam --progress 0 --record-log "$out"
