#!/usr/bin/env bash
# aslam-sim as a process on udpm://: in a private network namespace (or, if
# user namespaces are unavailable, on a port of its own with ttl=0) it
# publishes every channel, follows CMD_VEL-free scripted drives, and bad
# input stops it with a message naming the culprit.
#   sim_process_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
sim="$build/drivers/sim/aslam-sim"

port_base=7800
source "$src/tests/process_test_lib.sh"

"$monitor" --lcm-url "$url" --duration 4 --period 100 >"$out/monitor.txt" 2>&1 &
monitor_pid=$!
sleep 0.3
"$sim" --world "$src/worlds/test" --drive "$src/config/drives/test_loop.yaml" --duration 10 \
  --rate 4 --lcm-url "$url" --progress 5 >"$out/sim.txt" 2>&1
sim_rc=$?
wait $monitor_pid
cat "$out/sim.txt" "$out/monitor.txt"

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
