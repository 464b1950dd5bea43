#!/usr/bin/env bash
# aslam-sim as a process on udpm://: in a private network namespace (or, if
# user namespaces are unavailable, on a port of its own with ttl=0) it
# publishes every channel, follows CMD_VEL-free scripted drives, and bad
# input stops it with a message naming the culprit.
#   sim_process_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
sim="$build/drivers/aslam-sim"
monitor="$build/tools/aslam-monitor"

if [[ -z "${ASLAM_IN_NETNS:-}" ]] && unshare -rn true 2>/dev/null; then
  ASLAM_IN_NETNS=1 exec "$src/scripts/in-private-netns" "$0" "$@"
fi

url="udpm://239.255.76.67:$((7800 + $$ % 100))?ttl=0"
failures=0
check() {  # check NAME COMMAND...: runs the command, counts a failure
  local name="$1"
  shift
  if "$@"; then echo "ok: $name"; else echo "FAILED: $name"; failures=$((failures + 1)); fi
}

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

"$monitor" --lcm-url "$url" --duration 4 --period 100 >"$out/monitor.txt" 2>&1 &
monitor_pid=$!
sleep 0.3
"$sim" --world "$src/worlds/test" --drive "$src/config/drives/test_loop.yaml" --duration 10 \
  --rate 4 --lcm-url "$url" --progress 5 >"$out/sim.txt" 2>&1
sim_rc=$?
wait $monitor_pid
cat "$out/sim.txt" "$out/monitor.txt"

heard() {  # heard CHANNEL TYPE MIN: the monitor's last table has at least MIN messages
  awk -v c="$1" -v t="$2" -v min="$3" '$1 == c && $2 == t { n = $3 } END { exit !(n >= min) }' \
    "$out/monitor.txt"
}
check "aslam-sim exits 0 after --duration" test "$sim_rc" -eq 0
check "ran 10 simulated seconds" grep -q "stopped after 10.0 simulated s, 0 collisions" "$out/sim.txt"
check "LIDAR_SCAN heard" heard LIDAR_SCAN aslam.lidar_scan_t 90
check "ODOMETRY heard" heard ODOMETRY aslam.odometry_t 450
check "SIM_TRUTH heard" heard SIM_TRUTH aslam.pose_t 450
check "SIM_STATUS heard" heard SIM_STATUS aslam.sim_status_t 9

"$sim" --world "$src/worlds/no_such_world" --duration 1 --lcm-url "$url" >"$out/bad.txt" 2>&1
rc=$?
check "a missing world exits 1" test "$rc" -eq 1
check "... naming it" grep -q "no_such_world" "$out/bad.txt"

printf 'sim:\n  lidar:\n    num_beams: many\n' >"$out/bad.yaml"
"$sim" --world "$src/worlds/test" --config "$out/bad.yaml" --duration 1 --lcm-url "$url" >"$out/bad.txt" 2>&1
rc=$?
check "a bad config exits 1" test "$rc" -eq 1
check "... naming file, line, key and value" \
  grep -q "bad.yaml:3: sim.lidar.num_beams = 'many'" "$out/bad.txt"

"$sim" --world "$src/worlds/test" --start 0.0,0.0,0.0 --duration 1 --lcm-url "$url" >"$out/bad.txt" 2>&1
rc=$?
check "a start inside a wall exits 1" test "$rc" -eq 1

"$sim" --world "$src/worlds/test" --start 1,2 --duration 1 --lcm-url "$url" >"$out/bad.txt" 2>&1
rc=$?
check "a malformed --start exits 2" test "$rc" -eq 2

echo "$((12 - failures)) passed, $failures failed"
exit $((failures > 0))
