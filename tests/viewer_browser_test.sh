#!/usr/bin/env bash
# aslam-viewer in a real browser: lcm-logplayer replays logs/decision_fixture.lcmlog onto the
# bus, aslam-viewer serves the page, headless Chromium (driven by chromedriver over WebDriver
# on loopback) loads it. The map canvas is not blank, the frontier table has one row per
# frontier of the fixture's last FRONTIERS message, and a click on pause is answered and puts
# an EXPLORE_CONTROL PAUSE on the bus. The page's screenshot is kept in BUILD_DIR.
#   viewer_browser_test.sh SOURCE_DIR BUILD_DIR
# Exits 77 (skipped, with the reason) where Chromium or chromedriver is not installed.
set -uo pipefail
src="$1"
build="$2"

for tool in /usr/bin/chromium /usr/bin/chromedriver; do
  if [[ ! -x "$tool" ]]; then
    echo "SKIPPED: $tool is not installed (scripts/install-deps installs chromium and chromium-driver)"
    exit 77
  fi
done

port_base=7900
source "$src/tests/process_test_lib.sh"

viewer_port=$((18000 + $$ % 1000))
driver_port=$((19000 + $$ % 1000))
fixture="$src/logs/decision_fixture.lcmlog"
screenshot="$build/viewer_screenshot.png"

lcm-logger --lcm-url="$url" --channel=EXPLORE_CONTROL --quiet "$out/control.lcmlog" \
  >"$out/logger.txt" 2>&1 &
logger_pid=$!
"$build/viewer/aslam-viewer" --lcm-url "$url" --port "$viewer_port" --rate 2 >"$out/viewer.txt" 2>&1 &
viewer_pid=$!
chromedriver --port="$driver_port" --allowed-ips=127.0.0.1 >"$out/driver.txt" 2>&1 &
driver_pid=$!
trap 'kill $logger_pid $viewer_pid $driver_pid 2>/dev/null; rm -rf "$out"' EXIT
for _ in $(seq 50); do
  grep -q "aslam-viewer: open" "$out/viewer.txt" && break
  sleep 0.1
done

# The page loads while the fixture plays (4x: 10 s).
lcm-logplayer --lcm-url="$url" --speed=4 "$fixture" >"$out/player.txt" 2>&1 &
player_pid=$!
python3 "$src/tests/viewer_browser.py" check "$viewer_port" "$driver_port" "$fixture" \
  "$screenshot" >"$out/browser.txt" 2>&1
browser_rc=$?
wait $player_pid
sleep 0.5
kill -INT $logger_pid 2>/dev/null
wait $logger_pid 2>/dev/null
cat "$out/browser.txt"

while read -r line; do
  case "$line" in
    ok:*) passes=$((passes + 1)); echo "$line" ;;
    FAILED:*) failures=$((failures + 1)); echo "$line" ;;
  esac
done <"$out/browser.txt"
check "the browser checks ran to the end" test "$browser_rc" -ne 2
check "the screenshot was saved" test -s "$screenshot"
python3 "$src/tests/viewer_browser.py" lcm-log-summary "$out/control.lcmlog" >"$out/control.txt" 2>&1
cat "$out/control.txt"
# explore_control_t: 8-byte fingerprint, int64 utime, then the command: PAUSE = 01.
check "the click put one EXPLORE_CONTROL PAUSE on the bus" \
  test "$(awk '$1 == "EXPLORE_CONTROL" && substr($3, 33, 2) == "01"' "$out/control.txt" | wc -l)" -eq 1

kill -INT $viewer_pid 2>/dev/null
wait $viewer_pid
viewer_rc=$?
cat "$out/viewer.txt"
check "aslam-viewer ends cleanly on SIGINT" test "$viewer_rc" -eq 0

echo "$passes passed, $failures failed"
((failures == 0))
