#!/usr/bin/env bash
# Devices in the loop: aslam-sim --devices emulates a Kobuki and an RPLIDAR A2 on
# pseudo-terminals from the simulation, and the real driver processes (aslam-kobuki,
# aslam-rplidar) stand between it and the unchanged stack: `aslam explore --devices`
# explores worlds/office for 300 simulated seconds at real time. Checks the exploration
# (coverage, no collision, SLAM and the scans' stamps against truth), that the drivers
# carried the data (ODOMETRY at 50 Hz, LIDAR_SCAN at 10 Hz, BASE_STATUS, DRIVER_STATUS) and
# that nothing is left behind.
#   devices_in_the_loop_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
duration_s=300
port_base=8600
source "$src/tests/process_test_lib.sh"

run="$out/run"
"$build/eval/aslam" explore --world "$src/worlds/office" --method ours --seed 1 \
  --duration "$duration_s" --rate 1 --devices --config "$src/config/aslam.yaml" --lcm-url "$url" \
  --progress 30 --out "$run" >"$out/explore.txt" 2>&1
rc=$?
cat "$out/explore.txt"
[[ -f "$run/metrics.json" ]] && cat "$run/metrics.json"
json() {  # json KEY: the value of a top-level key of metrics.json
  sed -n "s/^  \"$1\": \(.*\),\?\$/\1/p" "$run/metrics.json" | sed 's/,$//'
}
# messages CHANNEL: the count aslam log-stats gives the channel in the run's log.
"$build/eval/aslam" log-stats "$run/run.lcmlog" >"$out/log_stats.txt" 2>&1
messages() { awk -v c="$1" '$1 == c && $2 ~ /^[0-9]+$/ { n = $2 } END { print n + 0 }' "$out/log_stats.txt"; }
at_least() { awk -v n="$1" -v min="$2" 'BEGIN { exit !(n >= min) }'; }

check "aslam explore exits 0" test "$rc" -eq 0
check "the run lasted its duration" test "$(json end_reason)" = '"duration"'
# The same world, seed and a simulated RPLIDAR A2 without the drivers reach 54-88 % at 300 s
# (seeds 1-3): a broken link (no scans, no odometry, a base that does not move) stays near the
# few per cent seen from the start.
check "coverage >= 0.35" awk -v c="$(json coverage)" 'BEGIN { exit !(c >= 0.35) }'
check "no collisions" test "$(json collisions)" = 0
check "SLAM matched to truth on the host clock (> 100 keyframes)" \
  at_least "$(json ate_matched_keyframes)" 101
# One 300 s run at real time is one trajectory of many: SLAM's drift where no loop closes sets
# its ATE (0.02-0.14 m in 10 of 11 runs of this build, 0.41 m in one; docs/results.md). The bound
# catches SLAM losing the robot. The drivers' timing, whose 16 ms error once added 0.1 m of ATE,
# is checked directly by the scan stamps below.
check "ATE RMSE < 0.5 m" awk -v a="$(json ate_rmse_m)" 'BEGIN { exit !(a < 0.5) }'
# The drivers' scan stamps against truth, over the scans taken in turns: a driver that left
# out a packet's transfer time would be 7 ms early; the emulated lidar before it looked from
# the pose of each beam's instant made the scans 16 ms early.
check "scans fitted to truth in turns (>= 20)" at_least "$(json scan_timing_scans)" 20
check "scan stamps within 5 ms of truth (median)" \
  awk -v t="$(json scan_stamp_late_ms)" 'BEGIN { exit !(t != "null" && t > -5 && t < 5) }'
check "ODOMETRY from aslam-kobuki at ~50 Hz" at_least "$(messages ODOMETRY)" $((duration_s * 45))
check "LIDAR_SCAN from aslam-rplidar at ~10 Hz" at_least "$(messages LIDAR_SCAN)" $((duration_s * 9))
check "BASE_STATUS at ~10 Hz" at_least "$(messages BASE_STATUS)" $((duration_s * 8))
check "DRIVER_STATUS from both drivers at 1 Hz" at_least "$(messages DRIVER_STATUS)" $((duration_s * 2 - 20))
check "aslam-kobuki connected to the emulated base" grep -q "connected to" "$run/kobuki.log"
check "aslam-rplidar found an A2" grep -q "RPLIDAR a2" "$run/rplidar.log"
check "the base saw no checksum error" grep -q "(0 checksum errors)" "$run/kobuki.log"

leftovers=$(ps -eo pid=,args= | grep -F -- "$url" | grep -v grep)
[[ -n "$leftovers" ]] && echo "left behind:" && echo "$leftovers"
check "no process of the run is left" test -z "$leftovers"
check "no device link is left" test ! -e "$run/devices/kobuki" -a ! -e "$run/devices/rplidar"

if ((failures > 0)); then  # a real-time run cannot be rerun as it was: keep it to look at
  kept="$build/Testing/devices_in_the_loop_run"
  rm -rf "$kept" && cp -r "$run" "$kept" && echo "the run folder is kept in $kept"
fi
echo "$passes passed, $failures failed"
exit $((failures > 0))
