#!/usr/bin/env bash
# aslam-teleop as a process on udpm:// (a private network namespace, or a port of its own with
# ttl=0): keys piped in with --stdin at the pace of a held key's auto-repeat; aslam-monitor
# counts CMD_VEL and lcm-logger records it, and the log is decoded to check the velocities:
# each key's, the limits of --config's robot: section, the dead man's zero soon after the last
# key, silence once idle, and zeros last of all after q. Without --stdin a pipe is refused.
#   teleop_process_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
teleop="$build/tools/aslam-teleop"

port_base=8800
source "$src/tests/process_test_lib.sh"

# Limits 0.4 m/s and 1.5 rad/s: level 4 of 10 drives at 0.16 m/s and 0.6 rad/s, level 5 at
# 0.2 and 0.75.
printf 'robot:\n  max_linear_mps: 0.4\n  max_angular_radps: 1.5\n' >"$out/robot.yaml"

keys() {  # what a user types: held keys repeat every 0.1 s
  sleep 0.3
  for _ in 1 2 3 4 5 6; do printf 'i'; sleep 0.1; done     # forward
  for _ in 1 2 3 4; do printf '\033[D'; sleep 0.1; done    # left arrow: turn left
  printf '+'                                                # both speeds a step up
  for _ in 1 2 3; do printf 'o'; sleep 0.1; done           # forward-right
  sleep 2.6                                                 # let go: dead man, then silence
  printf 'q'
  sleep 0.5
}

"$monitor" --lcm-url "$url" --period 100 >"$out/monitor.txt" 2>&1 &
monitor_pid=$!
lcm-logger --lcm-url="$url" --quiet --force "$out/cmd.lcmlog" >"$out/logger.txt" 2>&1 &
logger_pid=$!
sleep 0.5
keys | "$teleop" --stdin --lcm-url "$url" --config "$out/robot.yaml" >"$out/teleop.txt" 2>&1
teleop_rc=$?
sleep 0.3
kill -INT $monitor_pid $logger_pid
wait $monitor_pid $logger_pid
cat "$out/teleop.txt" "$out/monitor.txt"

# CMD_VEL of the log, one line per message: seconds (utime), linear m/s, angular rad/s.
python3 - "$out/cmd.lcmlog" >"$out/cmd.txt" <<'EOF'
import struct, sys
data = open(sys.argv[1], "rb").read()
pos = 0
while pos + 28 <= len(data):
    sync, _, _, channel_len, data_len = struct.unpack_from(">IqqII", data, pos)
    if sync != 0xEDA1DA01:
        sys.exit("bad sync word at byte %d" % pos)
    pos += 28
    channel = data[pos:pos + channel_len].decode()
    payload = data[pos + channel_len:pos + channel_len + data_len]
    pos += channel_len + data_len
    if channel == "CMD_VEL":
        _, utime, linear, angular = struct.unpack_from(">qqdd", payload)
        print("%.6f %.6f %.6f" % (utime * 1e-6, linear, angular))
EOF
echo "CMD_VEL as recorded (s, m/s, rad/s):"
awk '{ printf "  %s", $0 } NR % 4 == 0 { print "" } END { print "" }' "$out/cmd.txt"

count() {  # count LINEAR ANGULAR MIN: at least MIN messages carry this command
  awk -v l="$1" -v a="$2" -v min="$3" \
    'function abs(x) { return x < 0 ? -x : x }
     abs($2 - l) < 1e-6 && abs($3 - a) < 1e-6 { n++ } END { exit !(n >= min) }' "$out/cmd.txt"
}
within_limits() {
  awk '$2 > 0.4 + 1e-9 || $2 < -0.4 - 1e-9 || $3 > 1.5 + 1e-9 || $3 < -1.5 - 1e-9 { bad = 1 }
       END { exit bad }' "$out/cmd.txt"
}
# The last motion (forward-right, keys over 0.2 s) lasts its keys plus the dead man (0.6 s):
# 0.65 to 1.5 s from its first message to the first zero after it (q comes 2.6 s after the
# last key), and that zero comes within 0.35 s of the last non-zero message (the dead man
# fires, then publishes at once).
deadman_stops_in_time() {
  awk '$2 == 0.2 && $3 == -0.75 && !run_start { run_start = $1 }
       $2 != 0 || $3 != 0 { last_move = $1; zero = 0; next }
       !zero && last_move { zero = $1 }
       END { printf "  last motion %.2f s, first zero after it +%.2f s\n", zero - run_start,
               zero - last_move
             exit !(zero > 0 && zero - last_move <= 0.35 && zero - run_start >= 0.65 &&
                    zero - run_start <= 1.5) }' \
    "$out/cmd.txt"
}
# Idle after the zeros of a stop (1 s): a gap of at least 0.5 s before q's zeros.
falls_silent_when_idle() {
  awk '{ if (NR > 1 && $1 - prev > gap) gap = $1 - prev; prev = $1 }
       END { printf "  longest gap %.2f s\n", gap; exit !(gap >= 0.5) }' "$out/cmd.txt"
}
quit_sends_zeros() {  # after the idle gap, q's messages: at least 3, all zero
  awk '{ t[NR] = $1; moving[NR] = ($2 != 0 || $3 != 0) }
       END { for (i = 2; i <= NR; i++) if (t[i] - t[i - 1] >= 0.5) after = i
             if (!after) exit 1
             for (i = after; i <= NR; i++) if (moving[i]) exit 1
             exit !(NR - after + 1 >= 3) }' "$out/cmd.txt"
}

check "aslam-teleop exits 0 after q" test "$teleop_rc" -eq 0
check "... saying it sent a zero command" grep -q "quit; sent a zero command" "$out/teleop.txt"
check "CMD_VEL heard as velocity_command_t" heard CMD_VEL aslam.velocity_command_t 20
check "forward (i) at 4/10 of 0.4 m/s" count 0.16 0 4
check "turn left (left arrow) at 4/10 of 1.5 rad/s" count 0 0.6 2
check "forward-right (o) a step faster after +" count 0.2 -0.75 3
check "no command beyond the robot: section's limits" within_limits
check "the dead man stops the robot 0.6 s after the last key" deadman_stops_in_time
check "an idle aslam-teleop falls silent" falls_silent_when_idle
check "q sends zero commands last" quit_sends_zeros

"$teleop" --lcm-url "$url" </dev/null >"$out/refused.txt" 2>&1
rc=$?
cat "$out/refused.txt"
check "a stdin that is not a terminal is refused with 2" test "$rc" -eq 2
check "... saying so and naming --stdin" \
  grep -q "stdin is not a terminal.*--stdin" "$out/refused.txt"

echo "$passes passed, $failures failed"
exit $((failures > 0))
