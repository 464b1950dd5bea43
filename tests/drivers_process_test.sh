#!/usr/bin/env bash
# The drivers as processes against emulated devices: aslam-sim --devices makes a Kobuki and
# an RPLIDAR on pseudo-terminals, aslam-kobuki and aslam-rplidar open them and publish
# ODOMETRY, LIDAR_SCAN, BASE_STATUS and DRIVER_STATUS; aslam-teleop's keys (piped) drive the
# simulated base through aslam-kobuki. Then the devices vanish (the simulator is killed):
# both drivers say so, keep running and reconnect when a new simulator makes them again.
# SIGTERM ends each driver with 0.
#   drivers_process_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
sim="$build/drivers/sim/aslam-sim"
port_base=8700
source "$src/tests/process_test_lib.sh"

devices="$out/devices"
start_sim() {  # start_sim LOG: a simulator with the devices, 60 s at real time
  "$sim" --world "$src/worlds/test" --devices "$devices" --duration 60 --rate 1 --lcm-url "$url" \
    --progress 1 >"$1" 2>&1 &
  sim_pid=$!
}
start_sim "$out/sim1.txt"
for _ in $(seq 50); do [[ -e "$devices/kobuki" && -e "$devices/rplidar" ]] && break; sleep 0.1; done
"$build/drivers/kobuki/aslam-kobuki" --port "$devices/kobuki" --config "$src/config/aslam.yaml" \
  --lcm-url "$url" >"$out/kobuki.txt" 2>&1 &
kobuki_pid=$!
"$build/drivers/rplidar/aslam-rplidar" --port "$devices/rplidar" --model a2 \
  --config "$src/config/aslam.yaml" --lcm-url "$url" >"$out/rplidar.txt" 2>&1 &
rplidar_pid=$!
sleep 2
"$monitor" --lcm-url "$url" --duration 4 --period 100 >"$out/monitor.txt" 2>&1
# Forward for about 2 s: a key every 0.1 s holds the dead man.
pose_x() { sed -n 's/.*pose ( *\([-0-9.]*\),.*/\1/p' "$1" | tail -1; }
x_before=$(pose_x "$out/sim1.txt")
{ for _ in $(seq 20); do printf i; sleep 0.1; done; printf q; } |
  "$build/tools/aslam-teleop" --stdin --config "$src/config/aslam.yaml" --lcm-url "$url" \
    >"$out/teleop.txt" 2>&1
sleep 1.5
x_after=$(pose_x "$out/sim1.txt")
cat "$out/monitor.txt"
echo "--- the simulated base at x = $x_before m before the keys, $x_after m after"

check "ODOMETRY from aslam-kobuki (50 Hz)" heard ODOMETRY aslam.odometry_t 180
check "LIDAR_SCAN from aslam-rplidar (10 Hz)" heard LIDAR_SCAN aslam.lidar_scan_t 35
check "BASE_STATUS (10 Hz)" heard BASE_STATUS aslam.base_status_t 35
check "DRIVER_STATUS from both drivers (1 Hz each)" heard DRIVER_STATUS aslam.driver_status_t 7
check "teleop's keys moved the simulated base forward" \
  awk -v a="$x_before" -v b="$x_after" 'BEGIN { exit !(b - a > 0.1) }'

# The devices vanish: both drivers report it and retry.
kill -KILL $sim_pid
wait $sim_pid 2>/dev/null
sleep 2
check "aslam-kobuki is still running" kill -0 $kobuki_pid
check "aslam-rplidar is still running" kill -0 $rplidar_pid
check "aslam-kobuki said the base was gone" grep -q "gone\|no feedback\|no such device" "$out/kobuki.txt"
check "aslam-rplidar said the lidar was gone" grep -q "gone\|no answer\|no such device" "$out/rplidar.txt"
# A new simulator makes the devices again: the drivers find them.
start_sim "$out/sim2.txt"
sleep 5
"$monitor" --lcm-url "$url" --duration 3 --period 100 >"$out/monitor.txt" 2>&1
cat "$out/monitor.txt"
check "aslam-kobuki reconnected" test "$(grep -c "connected to" "$out/kobuki.txt")" -ge 2
check "ODOMETRY again" heard ODOMETRY aslam.odometry_t 120
check "LIDAR_SCAN again" heard LIDAR_SCAN aslam.lidar_scan_t 20

kill -TERM $kobuki_pid $rplidar_pid
wait $kobuki_pid
kobuki_rc=$?
wait $rplidar_pid
rplidar_rc=$?
kill -TERM $sim_pid
wait $sim_pid
cat "$out/kobuki.txt" "$out/rplidar.txt"
check "aslam-kobuki exits 0 on SIGTERM" test "$kobuki_rc" -eq 0
check "aslam-rplidar exits 0 on SIGTERM" test "$rplidar_rc" -eq 0
check "the simulator removed its device links" test ! -e "$devices/kobuki" -a ! -e "$devices/rplidar"

echo "$passes passed, $failures failed"
exit $((failures > 0))
