#!/usr/bin/env bash
# Regenerates logs/exploration_fixture.lcmlog (tests/exploration_replay_test.cc):
# the first simulated seconds of the whole stack exploring worlds/test in one
# process, keeping ODOMETRY, LIDAR_SCAN and POSE_GRAPH. Deterministic: a rerun
# writes the same bytes.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
"$build/tests/record_fixture" exploration "$root/logs/exploration_fixture.lcmlog" 90
