#!/usr/bin/env bash
# Regenerates logs/decision_fixture.lcmlog (tests/utility_replay_test.cc):
# 40 simulated seconds of the test-world loop with SLAM, frontier and utility
# nodes in one process, keeping their map, pose, graph, frontiers, scores and
# goals. Deterministic but for UTILITY_SCORES.compute_ms (wall clock, diagnostic only).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
"$build/tests/record_fixture" decision "$root/logs/decision_fixture.lcmlog" 40
