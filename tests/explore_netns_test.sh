#!/usr/bin/env bash
# `aslam explore` in process mode on a host without a multicast route: inside a network
# namespace of its own with no route at all (so LCM's udpm cannot open there, as on an isolated
# machine), it says so in one line, runs again in a private network namespace whose loopback
# carries multicast, and completes a short run. With no unshare to be had either, it fails at
# once saying how to add the route. Exits 77 (skipped) where unshare -rn is not permitted.
#   explore_netns_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
if ! unshare -rn true 2>/dev/null; then
  echo "skipped: unshare -rn is not permitted here"
  exit 77
fi
# The namespaces are this test's subject: it makes them itself.
port_base=8400
stay_in_this_namespace=1
source "$src/tests/process_test_lib.sh"

# COMMAND... in a fresh network namespace without any route (loopback down, no multicast).
without_route() { unshare -rn "$@"; }

check "no multicast route in the namespace" without_route sh -c '! ip route get 239.255.76.67 2>/dev/null'
cannot_open_lcm() { ! without_route "$build/tools/aslam-monitor" --lcm-url "$url" --duration 0.1; }
check "... so LCM's udpm cannot open there" cannot_open_lcm

without_route "$build/eval/aslam" explore --world "$src/worlds/test" --method fd --seed 1 \
  --duration 6 --rate 4 --config "$src/config/aslam.yaml" --lcm-url "$url" --progress 2 \
  --out "$out/run" >"$out/explore.txt" 2>&1
rc=$?
cat "$out/explore.txt"
check "aslam explore exits 0" test "$rc" -eq 0
check "one line says it runs in a private network namespace" \
  test "$(grep -c "no multicast route for .*; running again in a private network namespace" \
    "$out/explore.txt")" -eq 1
check "the run reached its duration" grep -q '"end_reason": "duration"' "$out/run/metrics.json"
check "the simulator was heard" grep -Eq '"sim_seconds": [1-9]' "$out/run/metrics.json"
check "the lcm log is not empty" test -s "$out/run/run.lcmlog"

# No unshare to be had (none on PATH): a clear error naming the fix, at once.
mkdir "$out/empty_path"
without_route env PATH="$out/empty_path" "$build/eval/aslam" explore --world "$src/worlds/test" \
  --duration 6 --lcm-url "$url" --out "$out/no_unshare" >"$out/no_unshare.txt" 2>&1
rc=$?
cat "$out/no_unshare.txt"
check "without unshare it exits 1" test "$rc" -eq 1
check "... saying how to add a route" \
  grep -q "sudo ip route add 224.0.0.0/4 dev lo" "$out/no_unshare.txt"
check "... and starting nothing" test ! -e "$out/no_unshare/metrics.json"
check "... nor claiming to run in a namespace" \
  test "$(grep -c "running again in a private" "$out/no_unshare.txt")" -eq 0

echo "$passes passed, $failures failed"
exit $((failures > 0))
