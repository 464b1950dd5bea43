#!/usr/bin/env bash
# The fault matrix (issue 16): process-mode explorations of worlds/test, 300 simulated s,
# one undisturbed and one per fault: SIGKILL of slam, frontier, utility or nav at a random
# time, SIGSTOP of slam for 5 s then SIGCONT, and a utility hung (SIGSTOP) for 60 s, then
# SIGKILLed. Each run completes (exit 0), reaches coverage >= 0.9 x the undisturbed run's,
# records the restart, and keyframe ids run on across it (graph.g2o: ids 0..N-1, no jump
# between consecutive keyframes).
#   fault_matrix_process_test.sh SOURCE_DIR BUILD_DIR [RATE [WORLD [DURATION_S]]]
# (another world, e.g. worlds/office at rate 3, for the issue's own setting)
# An undisturbed run that ends below 0.8 coverage is shown and run once more (see below).
set -uo pipefail
src="$1"
build="$2"
rate="${3:-5}"
world="${4:-$src/worlds/test}"
duration_s="${5:-300}"
port_base=8600
source "$src/tests/process_test_lib.sh"

seed=${ASLAM_FAULT_SEED:-$$}
RANDOM=$seed
echo "fault times drawn with seed $seed (ASLAM_FAULT_SEED=$seed reruns them)"
host_port=${url%%\?*}

top() {  # top RUN KEY: a top-level key of metrics.json
  sed -n "s/^  \"$2\": \(.*\),\?\$/\1/p" "$out/$1/metrics.json" | sed 's/,$//'
}
key() {  # key RUN PROCESS KEY: a key of metrics.json's "processes" entry of PROCESS
  sed -n "s/^    \"$2\": {.*\"$3\": \([^,}]*\).*/\1/p" "$out/$1/metrics.json"
}
pid_of() {  # pid_of PROCESS: the pid of this run's aslam-PROCESS
  pgrep -f -- "aslam-$1 --lcm-url $host_port" | head -1
}

# run NAME [FAULT PROCESS]: one exploration into $out/NAME, the fault injected at a random
# simulated time in [40, 160] s.
run() {
  local name="$1" fault="${2:-}" process="${3:-}"
  "$build/eval/aslam" explore --world "$world" --method ours --seed 1 \
    --duration "$duration_s" --rate "$rate" --config "$src/config/aslam.yaml" \
    --lcm-url "$url" --progress 30 --out "$out/$name" >"$out/$name.txt" 2>&1 &
  local explore_pid=$!
  if [[ -n "$fault" ]]; then
    local at_s=$((40 + RANDOM % 121))
    sleep "$(awk -v t="$at_s" -v r="$rate" 'BEGIN { print 1.0 + t / r }')"
    local pid
    pid=$(pid_of "$process")
    echo "$name: $fault $process (pid ${pid:-none}) at about ${at_s} simulated s" | tee -a "$out/faults.txt"
    if [[ -n "$pid" ]]; then
      if [[ "$fault" == stop ]]; then
        kill -STOP "$pid"
        sleep "$(awk -v r="$rate" 'BEGIN { print 5.0 / r }')"  # 5 simulated s
        kill -CONT "$pid"
      elif [[ "$fault" == hang ]]; then
        # Hung for 60 simulated s, then killed: long enough for the robot to finish its goal and
        # stand, so that no new map revision comes to prompt the restarted process.
        kill -STOP "$pid"
        sleep "$(awk -v r="$rate" 'BEGIN { print 60.0 / r }')"
        kill -KILL "$pid"
      else
        kill -KILL "$pid"
      fi
    fi
  fi
  wait "$explore_pid"
  echo "$?" >"$out/$name.rc"
  tail -n 4 "$out/$name.txt"
}

# The robot may roll up to ~0.3 m while its SLAM is down (the navigator stops on a stale pose),
# so consecutive keyframes lie < 1 m apart; a new map frame would put one back at the origin.
ids_continuous() {  # ids_continuous RUN: graph.g2o's ids run 0..N-1, neighbours < 1 m apart
  awk '/^VERTEX_SE2 / { if ($2 != n) bad = 1; if (n && (($3-x)^2 + ($4-y)^2) > 1.0) bad = 1;
                        x = $3; y = $4; n++ } END { exit bad || n < 10 }' "$out/$1/graph.g2o"
}

# What a run that ended short did: its summary and its processes' last words.
diagnose() {  # diagnose RUN
  echo "--- $1 ended at coverage $(top "$1" coverage); its summary and logs' last lines:"
  tail -n 3 "$out/$1.txt"
  for p in slam frontier utility nav; do tail -n 2 "$out/$1/$p.log" 2>/dev/null; done
}

run undisturbed
# The reference must be a whole exploration. One that ended early (seen once in CI: "done" at
# 53 % with 379 keyframes, never in 30 local runs) is shown, then run once more: the matrix
# tests crash survival, and the early end stays visible in the output and in the table.
if ! awk -v c="$(top undisturbed coverage)" 'BEGIN { exit !(c >= 0.8) }'; then
  diagnose undisturbed
  mv "$out/undisturbed" "$out/undisturbed_short" && mv "$out/undisturbed.txt" "$out/undisturbed_short.txt"
  mv "$out/undisturbed.rc" "$out/undisturbed_short.rc"
  echo "NOTE: the undisturbed run ended short; running it once more as the reference"
  run undisturbed
fi
run kill_slam kill slam
run kill_frontier kill frontier
run kill_utility kill utility
run kill_nav kill nav
run stop_slam stop slam
run hang_utility hang utility

reference=$(top undisturbed coverage)
echo "--- the matrix (coverage of the undisturbed run: $reference)"
runs="undisturbed kill_slam kill_frontier kill_utility kill_nav stop_slam hang_utility"
[[ -d "$out/undisturbed_short" ]] && runs="undisturbed_short $runs"
printf '%-17s %-5s %-9s %-8s %-7s %-10s %-9s %-10s %-12s %s\n' \
  run exit coverage ratio sim_s keyframes ate_m goals_r/f restarts end
for name in $runs; do
  restarts=""
  for p in slam frontier utility nav; do
    n=$(key "$name" "$p" restarts)
    [[ -n "$n" && "$n" != 0 ]] && restarts+="$p $n "
  done
  printf '%-17s %-5s %-9s %-8s %-7s %-10s %-9s %-10s %-12s %s\n' "$name" "$(cat "$out/$name.rc")" \
    "$(awk -v c="$(top "$name" coverage)" 'BEGIN { printf "%.3f", c }')" \
    "$(awk -v c="$(top "$name" coverage)" -v r="$reference" 'BEGIN { printf "%.3f", c / r }')" \
    "$(top "$name" sim_seconds)" "$(top "$name" keyframes)" \
    "$(awk -v a="$(top "$name" ate_rmse_m)" 'BEGIN { printf "%.3f", a }')" \
    "$(top "$name" goals_reached)/$(top "$name" goals_failed)" "${restarts:-none}" \
    "$(top "$name" end_reason)"
done
for name in kill_slam kill_frontier kill_utility kill_nav stop_slam hang_utility; do
  awk -v c="$(top "$name" coverage)" -v r="$reference" 'BEGIN { exit !(c < 0.9 * r) }' &&
    diagnose "$name"
done

check "the undisturbed run covers at least 0.8" awk -v c="$reference" 'BEGIN { exit !(c >= 0.8) }'
for name in undisturbed kill_slam kill_frontier kill_utility kill_nav stop_slam hang_utility; do
  check "$name: exits 0" test "$(cat "$out/$name.rc")" -eq 0
  check "$name: coverage >= 0.9 x the undisturbed run's" \
    awk -v c="$(top "$name" coverage)" -v r="$reference" 'BEGIN { exit !(c >= 0.9 * r) }'
  check "$name: keyframe ids run on" ids_continuous "$name"
done
for p in slam frontier utility nav; do
  check "kill_$p: $p restarted once, after SIGKILL" \
    test "$(key "kill_$p" "$p" restarts)" = 1 -a "$(key "kill_$p" "$p" last_signal)" = '"SIGKILL"'
done
check "kill_slam: the restarted slam resumed from its journal" \
  grep -q "resuming from its own journal" "$out/kill_slam/slam.log"
resumed_keyframes=$(sed -n 's/^aslam-slam: .*slam.journal: \([0-9]*\) keyframes.*/\1/p' \
  "$out/kill_slam/slam.log" | head -1)
echo "kill_slam: resumed with ${resumed_keyframes:-?} keyframes, ended with $(top kill_slam keyframes)"
check "kill_slam: the graph went on from the resumed keyframes" \
  test "$(top kill_slam keyframes)" -gt "${resumed_keyframes:-1000000}"
for name in kill_utility hang_utility; do
  check "$name: the restarted utility resumed its counts" \
    grep -q "aslam-utility: resuming from" "$out/$name/utility.log"
done
check "hang_utility: the restarted utility decided again" \
  test "$(top hang_utility decisions)" -gt "$(sed -n 's/^aslam-utility: resuming from .*: \([0-9]*\) decisions.*/\1/p' \
    "$out/hang_utility/utility.log" | head -1)"
check "stop_slam: no process restarted" test "$(key stop_slam slam restarts)" = 0

leftovers=$(ps -eo pid=,args= | grep -F -- "$host_port" | grep -v grep)
[[ -n "$leftovers" ]] && echo "left behind:" && echo "$leftovers"
check "no process of the runs is left" test -z "$leftovers"

echo "$failures failed"
exit $((failures > 0))
