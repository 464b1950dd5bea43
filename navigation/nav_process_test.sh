#!/usr/bin/env bash
# aslam-nav as a process on udpm:// (private network namespace, or a port of
# its own with ttl=0): answers every LIDAR_SCAN of a running aslam-sim with
# CMD_VEL and NAV_STATUS, SIGTERM publishes a final stop and exits 0, and a
# bad config stops it with file, line, key and value named.
#   nav_process_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
nav="$build/navigation/aslam-nav"
sim="$build/drivers/sim/aslam-sim"

port_base=7900
source "$src/tests/process_test_lib.sh"

"$nav" --lcm-url "$url" --config "$src/config/aslam.yaml" >"$out/nav.txt" 2>&1 &
nav_pid=$!
"$monitor" --lcm-url "$url" --duration 3 --period 100 >"$out/monitor.txt" 2>&1 &
monitor_pid=$!
sleep 0.3
"$sim" --world "$src/worlds/test" --duration 8 --rate 4 --lcm-url "$url" --progress 0 \
  >"$out/sim.txt" 2>&1
wait $monitor_pid
kill -TERM $nav_pid
wait $nav_pid
nav_rc=$?
cat "$out/nav.txt" "$out/monitor.txt"

check "CMD_VEL heard, one per scan" heard CMD_VEL aslam.velocity_command_t 60
check "NAV_STATUS heard" heard NAV_STATUS aslam.nav_status_t 60
check "SIGTERM exits 0" test "$nav_rc" -eq 0
check "... after publishing a stop" grep -q "aslam-nav: stopped; [0-9]* commands, 0 messages dropped" \
  "$out/nav.txt"

printf 'nav:\n  dwa:\n    horizon_s: soon\n' >"$out/bad.yaml"
"$nav" --lcm-url "$url" --config "$out/bad.yaml" >"$out/bad.txt" 2>&1
rc=$?
check "a bad config exits 1" test "$rc" -eq 1
check "... naming file, line, key and value" \
  grep -q "bad.yaml:3: nav.dwa.horizon_s = 'soon'" "$out/bad.txt"

echo "$((6 - failures)) passed, $failures failed"
exit $((failures > 0))
