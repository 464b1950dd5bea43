#!/usr/bin/env bash
# The pipeline as processes on one udpm:// bus: aslam-sim drives a loop of
# the test world, aslam-slam publishes SLAM_POSE, POSE_GRAPH and SLAM_MAP,
# aslam-frontier FRONTIERS, aslam-utility its scores and goals, aslam-nav
# answers every scan; SIGUSR1 and SIGTERM make aslam-slam write its map and
# graph; a bad config stops each process naming file, line, key and value.
#   pipeline_process_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
slam="$build/slam/aslam-slam"
nav="$build/navigation/aslam-nav"
frontier="$build/frontier/aslam-frontier"
utility="$build/utility/aslam-utility"
sim="$build/drivers/sim/aslam-sim"

port_base=8000
source "$src/tests/process_test_lib.sh"

"$slam" --lcm-url "$url" --config "$src/config/aslam.yaml" --out-dir "$out/run" >"$out/slam.txt" 2>&1 &
slam_pid=$!
"$nav" --lcm-url "$url" --config "$src/config/aslam.yaml" >"$out/nav.txt" 2>&1 &
nav_pid=$!
"$frontier" --lcm-url "$url" --config "$src/config/aslam.yaml" >"$out/frontier.txt" 2>&1 &
frontier_pid=$!
"$utility" --lcm-url "$url" --config "$src/config/aslam.yaml" >"$out/utility.txt" 2>&1 &
utility_pid=$!
"$monitor" --lcm-url "$url" --duration 6 --period 100 >"$out/monitor.txt" 2>&1 &
monitor_pid=$!
sleep 0.3
"$sim" --world "$src/worlds/test" --drive "$src/config/drives/test_loop.yaml" --duration 20 \
  --rate 4 --lcm-url "$url" --progress 0 >"$out/sim.txt" 2>&1
wait $monitor_pid
kill -USR1 $slam_pid
sleep 0.5
saved_on_request=$([[ -s "$out/run/graph.g2o" && -s "$out/run/map.yaml" ]] && echo yes || echo no)
kill -TERM $slam_pid $nav_pid $frontier_pid $utility_pid
wait $slam_pid
slam_rc=$?
wait $frontier_pid
frontier_rc=$?
wait $utility_pid
utility_rc=$?
wait $nav_pid
cat "$out/slam.txt" "$out/frontier.txt" "$out/utility.txt" "$out/monitor.txt"

check "SLAM_POSE heard, one per scan" heard SLAM_POSE aslam.pose_t 150
check "POSE_GRAPH heard" heard POSE_GRAPH aslam.pose_graph_t 10
check "SLAM_MAP heard, at most 1 Hz of sim time" heard SLAM_MAP aslam.compressed_occupancy_grid_t 5
check "aslam-nav answered with NAV_STATUS" heard NAV_STATUS aslam.nav_status_t 150
check "FRONTIERS heard, one per map" heard FRONTIERS aslam.frontier_list_t 5
check "UTILITY_SCORES heard" heard UTILITY_SCORES aslam.utility_scores_t 1
check "EXPLORE_GOAL heard" heard EXPLORE_GOAL aslam.explore_goal_t 1
check "EXPLORE_STATUS heard" heard EXPLORE_STATUS aslam.explore_status_t 5
check "aslam-frontier and aslam-utility exit 0 on SIGTERM" test "$frontier_rc" -eq 0 -a "$utility_rc" -eq 0
check "SIGUSR1 writes map and graph" test "$saved_on_request" = yes
check "SIGTERM exits 0" test "$slam_rc" -eq 0
check "... having written map.pgm and graph.g2o" test -s "$out/run/map.pgm" -a -s "$out/run/graph.g2o"
check "... with keyframes in the graph" grep -q "^VERTEX_SE2 20 " "$out/run/graph.g2o"

printf 'slam:\n  keyframe:\n    travel_m: -1\n' >"$out/bad.yaml"
"$slam" --lcm-url "$url" --config "$out/bad.yaml" >"$out/bad.txt" 2>&1
rc=$?
cat "$out/bad.txt"
check "a bad config exits 1" test "$rc" -eq 1
check "... naming file, line, key and value" grep -q "bad.yaml:3: slam.keyframe.travel_m" "$out/bad.txt"

printf 'frontier:\n  max_segment_length_m: long\n' >"$out/bad.yaml"
"$frontier" --lcm-url "$url" --config "$out/bad.yaml" >"$out/bad.txt" 2>&1
rc=$?
cat "$out/bad.txt"
check "aslam-frontier: a bad config exits 1" test "$rc" -eq 1
check "... naming file, line, key and value" grep -q "bad.yaml:2: frontier.max_segment_length_m" "$out/bad.txt"
printf 'utility:\n  method: best\n' >"$out/bad.yaml"
"$utility" --lcm-url "$url" --config "$out/bad.yaml" >"$out/bad.txt" 2>&1
rc=$?
cat "$out/bad.txt"
check "aslam-utility: a bad method exits 1 naming the key" test "$rc" -eq 1
check "... naming file, line, key and value" grep -q "bad.yaml:2: utility.method" "$out/bad.txt"

echo "$((19 - failures)) passed, $failures failed"
exit $((failures > 0))
