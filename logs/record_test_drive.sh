#!/usr/bin/env bash
# Regenerates logs/test_drive.lcmlog: 30 simulated seconds of aslam-sim
# following config/drives/test_loop.yaml in worlds/test (seed 7), recorded
# by lcm-logger on a private bus (its own network namespace when the
# machine allows, else a port of its own with ttl=0). Run after scripts/build.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
# Record in a private network namespace when the machine allows it.
if [[ -z "${ASLAM_IN_NETNS:-}" ]] && unshare -rn true 2>/dev/null; then
  ASLAM_IN_NETNS=1 exec scripts/in-private-netns "$0" "$@"
fi
url="udpm://239.255.76.67:7772?ttl=0"
out=logs/test_drive.lcmlog

lcm-logger --lcm-url="$url" --invert-channels --channel=LCM_SELF_TEST --force --quiet "$out" &
logger=$!
trap 'kill $logger 2>/dev/null || true' EXIT
sleep 0.5
build/drivers/sim/aslam-sim --world worlds/test --drive config/drives/test_loop.yaml --duration 30 \
  --rate 2 --seed 7 --config config/aslam.yaml --lcm-url "$url" --progress 10
sleep 0.5
kill -INT $logger
wait $logger || true
trap - EXIT
echo "wrote $out ($(stat -c %s "$out") bytes)"
