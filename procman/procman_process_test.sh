#!/usr/bin/env bash
# aslam-procman as processes on udpm:// (private network namespace, or a port
# of its own with ttl=0): the deputy restarts a child killed with SIGKILL and
# reports restarts = 1 in PROCMAN_STATUS; the sheriff stops and starts a
# process; lcm-logger, launched by it, records the bus; SIGTERM to the deputy
# leaves no child (nor grandchild) behind and, after a child failed with exit 3,
# exits non-zero; --exit-when ends a run cleanly with exit code 0.
#   procman_process_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
pm="$build/procman/aslam-procman"

port_base=8100
source "$src/tests/process_test_lib.sh"

wait_for() {  # wait_for TIMEOUT_S COMMAND...: true once the command succeeds
  local end=$((SECONDS + $1))
  shift
  until "$@"; do
    ((SECONDS < end)) || return 1
    sleep 0.2
  done
}
status() { "$pm" status --lcm-url "$url" --wait-s 3 >"$out/status.txt" 2>&1; }
col() {  # col NAME COLUMN: a column of NAME's row in the last status table
  awk -v n="$1" -v c="$2" '$1 == n { print $c }' "$out/status.txt"
}
is_state() { status && [[ "$(col "$1" 3)" == "$2" && "$(col "$1" 5)" == "$3" ]]; }  # NAME STATE RESTARTS

cat >"$out/launch.yaml" <<'YAML'
procman:
  deputy: test
  stop_timeout_s: 2
  processes:
    - name: logger
      command: lcm-logger
      args: ["--lcm-url=${LCM_URL}", --quiet, --force, "${OUT}/bus.lcmlog"]
      start_order: -1
    - name: a
      command: /bin/sleep
      args: ["300"]
      restart: on-failure
      backoff: {initial_s: 0.2}
    - name: b
      command: /bin/sh
      args: [-c, "sleep 300 & wait"]   # leaves a grandchild in its group
      group: naps
    - name: fails
      command: /bin/sh
      args: [-c, "exit 3"]
      restart: never
YAML

"$pm" deputy --config "$out/launch.yaml" --lcm-url "$url" --log-dir "$out/logs" \
  >"$out/deputy.txt" 2>&1 &
deputy=$!

check "status shows a running" wait_for 10 is_state a running 0
cat "$out/status.txt"
a_pid=$(col a 4)
check "... and fails as failed with exit code 3" test "$(col fails 3)/$(col fails 6)" = failed/3

kill -KILL "$a_pid"
check "SIGKILL a: restarted, PROCMAN_STATUS says restarts = 1" wait_for 10 is_state a running 1
cat "$out/status.txt"
check "... with a new pid and exit code -9" test "$(col a 4)" != "$a_pid" -a "$(col a 6)" = -9

b_pid=$(col b 4)
"$pm" stop naps --lcm-url "$url" >"$out/stop.txt" 2>&1
check "sheriff stop (by group) exits 0" test $? -eq 0
cat "$out/stop.txt"
check "... b stopped" is_state b stopped 0
check "... its process group is gone" wait_for 5 bash -c "! pgrep -g $b_pid >/dev/null"
"$pm" start b --lcm-url "$url" >"$out/start.txt" 2>&1
check "sheriff start exits 0" test $? -eq 0
check "... b running again" is_state b running 1
check "sheriff refuses an unknown name" bash -c "! '$pm' stop nobody --lcm-url '$url' --wait-s 3"

status
pids=$(awk '$4 ~ /^[0-9]+$/ && $4 > 0 { print $4 }' "$out/status.txt")
echo "children: $pids"
kill -TERM "$deputy"
wait "$deputy"
rc=$?
cat "$out/deputy.txt"
check "SIGTERM: the deputy exits non-zero after a child failed" test "$rc" -ne 0
check "... naming the failure" grep -q "failed: fails: exit code 3" "$out/deputy.txt"
none_left() {  # each child led its own group: nothing of any group may be left
  left=""
  for pid in $pids; do
    if kill -0 "$pid" 2>/dev/null || pgrep -g "$pid" >/dev/null; then left="$left $pid"; fi
  done
  [[ -z "$left" ]]
}
# An orphaned grandchild is a zombie until init reaps it: allow it a moment.
wait_for 5 none_left || ps -o pid,ppid,pgid,stat,args -g "$(echo $left | tr ' ' ,)"
check "... and leaves no child process (checked: $(echo $pids))" test -z "$left"
check "lcm-logger recorded the bus into the log dir" test -s "$out/logs/bus.lcmlog"
check "each process has its own log" test -f "$out/logs/a.log" -a -f "$out/logs/fails.log"

# --exit-when: the run ends when `sim` ends; the others are stopped; exit code 0.
cat >"$out/run.yaml" <<'YAML'
procman:
  processes:
    - {name: slam, command: /bin/sleep, args: ["300"], restart: always}
    - {name: sim, command: /bin/sh, args: [-c, "sleep 1"], start_order: 1}
YAML
timeout 20 "$pm" deputy --config "$out/run.yaml" --lcm-url "$url" --log-dir "$out/run" \
  --exit-when sim >"$out/run.txt" 2>&1
rc=$?
cat "$out/run.txt"
check "--exit-when sim: the deputy exits 0 after stopping the rest" test "$rc" -eq 0
check "... having stopped slam" grep -q "killed by signal 15" "$out/run/slam.log"

echo "$((16 - failures)) passed, $failures failed"
exit $((failures > 0))
