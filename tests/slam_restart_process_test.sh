#!/usr/bin/env bash
# aslam-slam killed with SIGKILL mid-lap and started again with the same command
# resumes from its journal: same keyframe ids (the graph continues from where it
# stopped, no keyframe 0 again), same "map" frame (the first keyframe after the
# restart lies next to the last one before it), and the lap's loop still closes.
#   slam_restart_process_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
slam="$build/slam/aslam-slam"
sim="$build/drivers/sim/aslam-sim"

port_base=8500
source "$src/tests/process_test_lib.sh"

run="$out/run"
start_slam() {
  "$slam" --lcm-url "$url" --config "$src/config/aslam.yaml" --out-dir "$run" --journal-dir "$run" \
    >>"$out/slam.txt" 2>&1 &
  slam_pid=$!
}
vertices() { grep -c '^VERTEX_SE2 ' "$run/graph.g2o"; }

start_slam
sleep 0.3
"$sim" --world "$src/worlds/test" --drive "$src/config/drives/test_loop.yaml" --duration 110 \
  --rate 5 --lcm-url "$url" --progress 0 >"$out/sim.txt" 2>&1 &
sim_pid=$!
sleep 6  # about 30 s of the lap
kill -USR1 $slam_pid
sleep 0.5
before=$(vertices)
kill -KILL $slam_pid
killed_ns=$(date +%s%N)
wait $slam_pid 2>/dev/null
echo "--- killed aslam-slam with $before keyframes written; restarting"
start_slam
# The lap goes on while SLAM is down, so the gap across the restart grows with the
# downtime: time it until the journal is loaded (the first keyframe follows at once).
for _ in $(seq 200); do grep -q "slam.journal: [0-9]* keyframes" "$out/slam.txt" && break; sleep 0.1; done
down_s=$(awk -v a="$killed_ns" -v b="$(date +%s%N)" 'BEGIN { printf "%.2f", (b - a) / 1e9 }')
wait $sim_pid
sleep 0.5
kill -TERM $slam_pid
wait $slam_pid
slam_rc=$?
cat "$out/slam.txt"
after=$(vertices)
echo "--- $before keyframes before the kill, $after at the end"

check "the restarted aslam-slam resumed from its journal" grep -q "resuming from its own journal" "$out/slam.txt"
check "... and exited 0 on SIGTERM" test "$slam_rc" -eq 0
check "the graph kept growing after the restart" test "$after" -gt $((before + 20))
check "keyframe ids run 0..N-1 with none twice" \
  awk '/^VERTEX_SE2 / { if ($2 != n) bad = 1; n++ } END { exit bad }' "$run/graph.g2o"
# Consecutive keyframes are at most ~0.45 m apart, plus what the lap drove while SLAM was
# down (0.4 m/s at --rate 5, 1 s slack for the first scan); a new map frame would put the
# first keyframe after the restart back at the origin, about 11 m away.
max_gap_m=$(awk -v d="$down_s" 'BEGIN { printf "%.2f", 0.6 + 0.4 * 5 * (d + 1.0) }')
largest_gap_m=$(awk '/^VERTEX_SE2 / { if (n) { g = sqrt(($3-x)^2 + ($4-y)^2); if (g > m) m = g }
  x = $3; y = $4; n++ } END { printf "%.2f", m }' "$run/graph.g2o")
echo "--- SLAM down for $down_s s; largest gap between consecutive keyframes $largest_gap_m m (bound $max_gap_m m)"
check "no jump between consecutive keyframes (same map frame)" \
  awk -v g="$largest_gap_m" -v m="$max_gap_m" 'BEGIN { exit !(g <= m && m < 10) }'
check "the lap's loop closed" grep -q "loop closures [1-9]" "$out/slam.txt"
check "the journal is in the run folder" test -s "$run/slam.journal"

echo "$failures failed"
exit $((failures > 0))
