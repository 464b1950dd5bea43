#!/usr/bin/env bash
# `aslam explore` in process mode when a process crashes (docs/architecture.md §8):
# 1. aslam-nav is killed with SIGKILL once, a few seconds into the run: procman restarts it,
#    the run completes and exits 0, and metrics.json, process_stats.json and the progress line
#    record the restart and the signal.
# 2. aslam-utility crashes at every start: procman gives up after
#    backoff.give_up_after_failures, and aslam explore ends the run at once, says why on
#    stderr, records end_reason "process-failed" and exits non-zero.
# Both runs use config/launch/explore.yaml with one command swapped for a wrapper.
#   explore_failures_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
port_base=8300
source "$src/tests/process_test_lib.sh"

launch="$src/config/launch/explore.yaml"
explore() {  # explore NAME LAUNCH DURATION: a short process-mode run into $out/NAME
  "$build/eval/aslam" explore --world "$src/worlds/test" --method fd --seed 1 --duration "$3" \
    --rate 5 --config "$src/config/aslam.yaml" --lcm-url "$url" --progress 2 \
    --launch "$2" --out "$out/$1" >"$out/$1.txt" 2>&1
}
swap() {  # swap PROCESS WRAPPER OUT_YAML: the launch config with PROCESS's command replaced
  sed "s|command: \${BUILD}/[a-z]*/aslam-$1\$|command: $2|" "$launch" >"$3"
  grep -q "command: $2\$" "$3"
}
key() {  # key RUN PROCESS KEY: a key of metrics.json's "processes" entry of PROCESS
  sed -n "s/^    \"$2\": {.*\"$3\": \([^,}]*\).*/\1/p" "$out/$1/metrics.json"
}
top() {  # top RUN KEY: a top-level key of metrics.json
  sed -n "s/^  \"$2\": \(.*\),\?\$/\1/p" "$out/$1/metrics.json" | sed 's/,$//'
}

# 1. The first aslam-nav is killed 2 s (about 10 simulated s) after it started; later ones run.
cat >"$out/nav_killed_once" <<EOF
#!/bin/sh
if [ ! -e "$out/nav_was_killed" ]; then
  touch "$out/nav_was_killed"
  (sleep 2; kill -9 \$\$) &
fi
exec "$build/navigation/aslam-nav" "\$@"
EOF
chmod +x "$out/nav_killed_once"
check "launch config with the nav wrapper" swap nav "$out/nav_killed_once" "$out/nav_once.yaml"
explore restarted "$out/nav_once.yaml" 40
rc=$?
cat "$out/restarted.txt"
cat "$out/restarted/metrics.json" 2>/dev/null
check "a run with a restarted process exits 0" test "$rc" -eq 0
check "... and reaches its duration" test "$(top restarted end_reason)" = '"duration"'
check "the wrapper did kill nav" test -e "$out/nav_was_killed"
check "metrics.json: nav restarted once" test "$(key restarted nav restarts)" = 1
check "metrics.json: nav last ended by SIGKILL" test "$(key restarted nav last_signal)" = '"SIGKILL"'
check "metrics.json: ... with no exit code" test "$(key restarted nav last_exit_code)" = null
check "metrics.json: slam never restarted" test "$(key restarted slam restarts)" = 0
check "metrics.json: ... nor ended on its own" test "$(key restarted slam last_signal)" = null
check "process_stats.json: nav restarted once, by SIGKILL" \
  grep -Eq '"name": "nav".*"restarts": 1, "last_exit_code": null, "last_signal": "SIGKILL"' \
  "$out/restarted/process_stats.json"
check "the progress line shows the restart" grep -q "restarts: nav 1" "$out/restarted.txt"
check "the summary names the restart" \
  grep -q "processes restarted during the run: nav 1 (last ends: nav SIGKILL" "$out/restarted.txt"

# 2. aslam-utility dies at every start; explore.yaml gives up after 5 failures in a row.
printf '#!/bin/sh\nkill -9 $$\n' >"$out/utility_always_crashes"
chmod +x "$out/utility_always_crashes"
check "launch config with the utility wrapper" \
  swap utility "$out/utility_always_crashes" "$out/utility_crashes.yaml"
start_s=$SECONDS
explore gave_up "$out/utility_crashes.yaml" 300
rc=$?
cat "$out/gave_up.txt"
cat "$out/gave_up/metrics.json" 2>/dev/null
check "a run whose process was given up on exits non-zero" test "$rc" -eq 1
check "... with end_reason process-failed" test "$(top gave_up end_reason)" = '"process-failed"'
check "... long before its duration" awk -v t="$(top gave_up sim_seconds)" 'BEGIN { exit !(t < 100) }'
check "stderr says which process and why" \
  grep -q "the run stopped at .* utility ended (SIGKILL) after 4 restarts and procman will not restart it" \
  "$out/gave_up.txt"
check "metrics.json: utility restarted 4 times" test "$(key gave_up utility restarts)" = 4
check "metrics.json: ... last ended by SIGKILL" test "$(key gave_up utility last_signal)" = '"SIGKILL"'
check "procman says it gave up" grep -q "gave up after 5 failures in a row" "$out/gave_up/utility.log"
echo "--- the second run took $((SECONDS - start_s)) s wall"

leftovers=$(ps -eo pid=,args= | grep -F -- "$url" | grep -v grep)
[[ -n "$leftovers" ]] && echo "left behind:" && echo "$leftovers"
check "no process of the runs is left" test -z "$leftovers"

echo "$passes passed, $failures failed"
exit $((failures > 0))
