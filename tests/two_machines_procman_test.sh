#!/usr/bin/env bash
# The deputy on the robot, the sheriff and a bus monitor (lcm-spy's stand-in) on a laptop: two
# network namespaces, "robot" and "laptop", joined by a veth pair on one subnet (10.76.0.1/24,
# 10.76.0.2/24), each with its multicast route 224.0.0.0/4 on its veth end, as two machines on
# one network. With the README's two-machine URL (udpm, ttl=1) the laptop's `aslam-procman
# start|stop|restart|status` drive the robot's deputy: every change shows in the status table the
# laptop hears (PROCMAN_STATUS) and in the processes in the robot's namespace (pids alive or gone,
# in the robot's network namespace, not the laptop's). With the project's default ttl=0 nothing
# crosses: the robot hears its own deputy, the laptop hears nothing at all.
#   two_machines_procman_test.sh SOURCE_DIR BUILD_DIR
# Runs as any user where unprivileged user namespaces are allowed (unshare -rn); exits 77
# (skipped) with the reason where they are not, or where no veth pair can be made.
set -uo pipefail
export PATH=$PATH:/usr/sbin:/sbin  # ip, for a user whose PATH lacks it
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
pm="$build/procman/aslam-procman"

if [[ -z ${ASLAM_TWO_MACHINES:-} ]]; then
  for tool in unshare nsenter ip; do
    command -v "$tool" >/dev/null || { echo "SKIPPED: $tool is not installed"; exit 77; }
  done
  if ! unshare -rn true 2>/dev/null; then
    echo "SKIPPED: unshare -rn is not permitted here (no unprivileged user namespaces)"
    exit 77
  fi
  # The test's own user, network and (where /proc can be mounted) PID namespace: when the test
  # ends, even by SIGKILL at its timeout, the kernel ends every process it started and with
  # them the namespaces. The two machines are network namespaces nested inside.
  isolate=(unshare -rn)
  if unshare -rn --pid --fork --kill-child --mount-proc true 2>/dev/null; then
    isolate=(unshare -rn --pid --fork --kill-child --mount-proc)
  fi
  ASLAM_TWO_MACHINES=1 exec "${isolate[@]}" "$0" "$@"
fi

# check and heard (process_test_lib.sh); the namespaces are this test's subject: it makes them.
port_base=8700
stay_in_this_namespace=1
source "$src/tests/process_test_lib.sh"
port=8731
url0="udpm://239.255.76.67:$port?ttl=0"  # the default: never leaves the machine
url1="udpm://239.255.76.67:$port?ttl=1"  # the README's URL for a robot and a laptop

robot_ns="" laptop_ns="" deputy="" monitors=()
stop_pid() {  # stop_pid PID: TERM, then KILL after 5 s; reaps it
  kill -TERM "$1" 2>/dev/null || return 0
  for _ in $(seq 50); do kill -0 "$1" 2>/dev/null || break; sleep 0.1; done
  kill -KILL "$1" 2>/dev/null
  wait "$1" 2>/dev/null
}
cleanup() {
  local pid
  for pid in "${monitors[@]}" $deputy $robot_ns $laptop_ns; do stop_pid "$pid"; done
  rm -rf "$out"
}
trap cleanup EXIT

wait_for() {  # wait_for TIMEOUT_S COMMAND...: true once the command succeeds
  local end=$((SECONDS + $1))
  shift
  until "$@"; do
    ((SECONDS < end)) || return 1
    sleep 0.2
  done
}
# A machine is a network namespace, held open by a sleeping process.
holder() { if [[ $1 == laptop ]]; then echo "$laptop_ns"; else echo "$robot_ns"; fi; }
# on MACHINE COMMAND...: runs the command there. In the background, run `nsenter -t "$(holder
# MACHINE)" -n COMMAND... &` instead: nsenter execs the command, so $! is the command's pid.
on() {
  local machine=$1
  shift
  nsenter -t "$(holder "$machine")" -n "$@"
}
netns_of() { readlink "/proc/$1/ns/net" 2>/dev/null; }
# PID is alive and in MACHINE's network namespace (so not in the other's).
runs_on() {  # runs_on MACHINE PID
  [[ $2 =~ ^[1-9][0-9]*$ ]] && kill -0 "$2" 2>/dev/null &&
    [[ "$(netns_of "$2")" == "$(netns_of "$(holder "$1")")" ]]
}
gone() { ! kill -0 "$1" 2>/dev/null; }
fails() { ! "$@"; }

# --- the two machines ---------------------------------------------------------------------------
unshare -n sleep infinity &
robot_ns=$!
unshare -n sleep infinity &
laptop_ns=$!
namespaces_up() {  # each holder has left the test's own network namespace
  local own
  own=$(netns_of $$)
  [[ "$(netns_of "$robot_ns")" != "$own" && "$(netns_of "$laptop_ns")" != "$own" ]]
}
wait_for 5 namespaces_up || {
  echo "FAILED: the namespaces did not come up"
  exit 1
}
if ! ip link add veth-robot netns "$robot_ns" type veth peer name veth-laptop netns "$laptop_ns" \
  2>"$out/veth.txt"; then
  echo "SKIPPED: no veth pair can be made here: $(head -1 "$out/veth.txt")"
  exit 77
fi
setup() {  # setup MACHINE DEVICE ADDRESS
  on "$1" ip link set lo up &&
    on "$1" ip addr add "$3/24" dev "$2" &&
    on "$1" ip link set "$2" up multicast on &&
    on "$1" ip route add 224.0.0.0/4 dev "$2"
}
check "robot: lo up, veth-robot 10.76.0.1/24 up, multicast route" setup robot veth-robot 10.76.0.1
check "laptop: lo up, veth-laptop 10.76.0.2/24 up, multicast route" \
  setup laptop veth-laptop 10.76.0.2
multicast_via() { on "$1" ip route get 239.255.76.67 | grep -q "dev $2 "; }
check "the robot's multicast goes out on its veth" multicast_via robot veth-robot
check "... and the laptop's on its own" multicast_via laptop veth-laptop
check "... two machines: two network namespaces" \
  test "$(netns_of "$robot_ns")" != "$(netns_of "$laptop_ns")"

cat >"$out/launch.yaml" <<'YAML'
procman:
  deputy: robot
  stop_timeout_s: 2
  processes:
    - name: lidar
      command: sleep
      args: ["1000"]
      group: sensors
      auto_start: false
    - name: base
      command: sleep
      args: ["1000"]
      group: sensors
      auto_start: false
    - name: heartbeat
      command: /bin/sh
      args: [-c, "while :; do date +%s > '${OUT}/heartbeat'; sleep 0.5; done"]
      group: tools
YAML

# DEPUTY_URL: the deputy in the robot's namespace, logs in $out/logs-TTL.
start_deputy() {
  local ttl=${1##*=}
  nsenter -t "$robot_ns" -n "$pm" deputy --config "$out/launch.yaml" --lcm-url "$1" \
    --log-dir "$out/logs-$ttl" >"$out/deputy-$ttl.txt" 2>&1 &
  deputy=$!
}
stop_deputy() {
  stop_pid "$deputy"
  deputy=""
}
status() {  # status MACHINE URL: the sheriff's status table, heard on that machine
  on "$1" "$pm" status --lcm-url "$2" --wait-s 3 >"$out/status.txt" 2>&1
}
col() {  # col NAME COLUMN: a column of NAME's row in the last status table
  awk -v n="$1" -v c="$2" '$1 == n { print $c }' "$out/status.txt"
}
state_is() {  # state_is NAME STATE on the laptop's last table
  [[ "$(col "$1" 3)" == "$2" ]]
}
laptop_sees() {  # laptop_sees NAME STATE...: a fresh table from the laptop shows these states
  status laptop "$url1" || return 1
  while (($#)); do
    state_is "$1" "$2" || return 1
    shift 2
  done
}
sheriff() {  # sheriff VERB TARGET: from the laptop, over the two-machine URL
  on laptop "$pm" "$1" "$2" --lcm-url "$url1" >"$out/sheriff.txt" 2>&1
  local rc=$?
  cat "$out/sheriff.txt"
  return "$rc"
}

# --- ttl=0 (the default): nothing crosses -------------------------------------------------------
start_deputy "$url0"
robot_sees_heartbeat() { status robot "$url0" && state_is heartbeat running; }
check "ttl=0: the robot hears its own deputy" wait_for 10 robot_sees_heartbeat
cat "$out/status.txt"
on laptop "$build/tools/aslam-monitor" --lcm-url "$url0" --duration 3 >"$out/monitor.txt" 2>&1
rc=$?
check "ttl=0: the laptop's monitor hears no message in 3 s (exit 3)" test "$rc" -eq 3
check "... not one PROCMAN_STATUS" fails grep -q PROCMAN_STATUS "$out/monitor.txt"
on laptop "$pm" status --lcm-url "$url0" --wait-s 2 >"$out/status0.txt" 2>&1
rc=$?
cat "$out/status0.txt"
check "ttl=0: the laptop's sheriff hears no deputy" \
  test "$rc" -ne 0 -a "$(grep -c "no PROCMAN_STATUS heard" "$out/status0.txt")" -eq 1
stop_deputy
rm -f "$out/monitor.txt"

# --- ttl=1: the sheriff on the laptop drives the deputy on the robot ----------------------------
start_deputy "$url1"
deputy1=$deputy
for machine in laptop robot; do  # lcm-spy's stand-in on each side, for the whole session
  nsenter -t "$(holder $machine)" -n "$build/tools/aslam-monitor" --lcm-url "$url1" \
    >"$out/monitor-$machine.txt" 2>&1 &
  monitors+=($!)
done

check "ttl=1: the laptop sees the deputy: heartbeat running, sensors stopped" \
  wait_for 10 laptop_sees heartbeat running lidar stopped base stopped
cat "$out/status.txt"
deputy_pid=$(awk '$1 == "deputy" && $2 == "robot" { sub(/\)/, "", $4); print $4 }' \
  "$out/status.txt")
check "... from deputy 'robot' (pid $deputy_pid): the one started in the robot's namespace" \
  test "$deputy_pid" = "$deputy1" -a "$(runs_on robot "$deputy_pid" && echo yes)" = yes
heartbeat=$(col heartbeat 4)
check "... heartbeat's pid $heartbeat runs in the robot's namespace" runs_on robot "$heartbeat"
check "... and not in the laptop's" \
  test "$(netns_of "$heartbeat")" != "$(netns_of "$laptop_ns")"

check "laptop: aslam-procman start sensors exits 0" sheriff start sensors
check "... the laptop sees lidar and base running" \
  laptop_sees lidar running base running heartbeat running
lidar=$(col lidar 4)
base=$(col base 4)
check "... lidar (pid $lidar) runs in the robot's namespace" runs_on robot "$lidar"
check "... base (pid $base) runs in the robot's namespace" runs_on robot "$base"
check "... as the launch file says (sleep 1000)" \
  test "$(tr '\0' ' ' <"/proc/$base/cmdline" 2>/dev/null)" = "sleep 1000 "

check "laptop: aslam-procman stop lidar exits 0" sheriff stop lidar
check "... the laptop sees lidar stopped, base running" laptop_sees lidar stopped base running
check "... lidar's process is gone from the robot" wait_for 5 gone "$lidar"
check "... base still runs there, the same pid" \
  test "$(col base 4)" = "$base" -a "$(runs_on robot "$base" && echo yes)" = yes

check "laptop: aslam-procman restart base exits 0" sheriff restart base
check "... the laptop sees base running" laptop_sees base running lidar stopped
new_base=$(col base 4)
check "... under a new pid ($base -> $new_base)" test "$new_base" != "$base"
check "... the old base is gone from the robot" wait_for 5 gone "$base"
check "... the new one runs in the robot's namespace" runs_on robot "$new_base"
check "laptop: the sheriff refuses an unknown name" \
  fails on laptop "$pm" stop nobody --lcm-url "$url1" --wait-s 3 2>"$out/nobody.txt"
check "... naming the known ones" grep -q "known: lidar(sensors) base(sensors) heartbeat(tools)" \
  "$out/nobody.txt"
check "the heartbeat ran on throughout" runs_on robot "$heartbeat"

# The monitors: the laptop heard the robot's status, the robot heard the laptop's orders.
for pid in "${monitors[@]}"; do stop_pid "$pid"; done
monitors=()
for machine in laptop robot; do
  echo "$machine's monitor:"
  sed -n '/^final:/,$p' "$out/monitor-$machine.txt"
done
cp "$out/monitor-laptop.txt" "$out/monitor.txt"
check "the laptop's monitor heard PROCMAN_STATUS from the robot" \
  heard PROCMAN_STATUS aslam.procman_status_t 5
cp "$out/monitor-robot.txt" "$out/monitor.txt"
check "the robot's monitor heard PROCMAN_ORDERS from the laptop" \
  heard PROCMAN_ORDERS aslam.procman_orders_t 3

# The deputy ends on SIGTERM, taking its children with it.
kill -TERM "$deputy1"
wait "$deputy1"
rc=$?
deputy=""
cat "$out/deputy-1.txt"
check "SIGTERM: the deputy exits 0" test "$rc" -eq 0
children_gone() { gone "$heartbeat" && gone "$new_base"; }
check "... leaving no child on the robot" wait_for 5 children_gone
check "... having obeyed every order (none ignored)" grep -q " 0 orders ignored" "$out/deputy-1.txt"

echo "$passes passed, $failures failed"
exit $((failures > 0))
