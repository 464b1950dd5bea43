#!/usr/bin/env bash
# `aslam explore` in process mode: aslam-procman runs sim, slam, frontier,
# utility, nav and lcm-logger on a private udpm:// URL (in a network
# namespace of its own when allowed), the runner listens on it. The
# exploration of worlds/test completes (`done`) with coverage >= 0.9, the
# run folder holds the outputs and a non-empty lcm log, and no process of
# the run is left behind.
#   explore_process_test.sh SOURCE_DIR BUILD_DIR [RATE]
set -uo pipefail
src="$1"
build="$2"
rate="${3:-${ASLAM_EXPLORE_TEST_RATE:-6}}"

# Process mode is not deterministic: the same seed explores worlds/test in 210-305
# simulated s (thread and UDP timing), so the bound is the run's duration, not a tight time.
duration_s=480
port_base=8200
source "$src/tests/process_test_lib.sh"

run="$out/run"
start_s=$SECONDS
"$build/eval/aslam" explore --world "$src/worlds/test" --method ours --seed 1 --duration "$duration_s" \
  --rate "$rate" --config "$src/config/aslam.yaml" --lcm-url "$url" --progress 20 --out "$run" \
  >"$out/explore.txt" 2>&1
rc=$?
wall_s=$((SECONDS - start_s))
cat "$out/explore.txt"
echo "--- wall ${wall_s} s at --rate $rate on $url"
[[ -f "$run/metrics.json" ]] && cat "$run/metrics.json"

json() {  # json KEY: the value of a top-level key of metrics.json
  sed -n "s/^  \"$1\": \(.*\),\?\$/\1/p" "$run/metrics.json" | sed 's/,$//'
}

check "aslam explore exits 0" test "$rc" -eq 0
check "the exploration is done" test "$(json done)" = true
check "... by the utility's done" test "$(json end_reason)" = '"done"'
check "... before the duration" awk -v t="$(json sim_seconds)" -v d="$duration_s" 'BEGIN { exit !(t > 0 && t < d) }'
check "coverage >= 0.9" awk -v c="$(json coverage)" 'BEGIN { exit !(c >= 0.9) }'
check "no collisions" test "$(json collisions)" = 0
check "ATE measured (keyframes matched to truth)" awk -v n="$(json ate_matched_keyframes)" 'BEGIN { exit !(n > 10) }'
check "metrics.json says mode process" test "$(json mode)" = '"process"'
for f in map.yaml map.pgm map.png graph.g2o coverage.csv uncertainty.csv metrics.json config.yaml procman.log; do
  check "run folder has $f" test -s "$run/$f"
done
check "the lcm log is not empty" test -s "$run/run.lcmlog"
check "... and larger than 100 kB (the whole run)" test "$(stat -c %s "$run/run.lcmlog" 2>/dev/null || echo 0)" -gt 100000
for p in sim slam frontier utility nav lcm-logger; do
  check "procman logged $p" test -e "$run/$p.log"
done
check "coverage.csv rises to >= 0.9" awk -F, 'NR > 1 && $2 >= 0.9 { ok = 1 } END { exit !ok }' "$run/coverage.csv"
check "the progress line was printed" grep -q "coverage .* keyframes" "$out/explore.txt"

leftovers=$(ps -eo pid=,args= | grep -F -- "$url" | grep -v grep)
[[ -n "$leftovers" ]] && echo "left behind:" && echo "$leftovers"
check "no process of the run is left" test -z "$leftovers"
check "process_stats.json names the slam process" grep -q '"name": "slam"' "$run/process_stats.json"
check "... and matched scans to commands" grep -Eq '"matched": [1-9]' "$run/process_stats.json"

if ((failures > 0)) && [[ -s "$run/run.lcmlog" ]]; then
  "$build/tests/print_goal_timeline" "$run/run.lcmlog"
fi

total=30
echo "$((total - failures)) passed, $failures failed"
exit $((failures > 0))
