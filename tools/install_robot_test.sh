#!/usr/bin/env bash
# scripts/install-robot --dry-run against a stand-in build in a temporary folder: the plan
# installs the binaries under the prefix, names the udev rules, the systemd unit and the launch
# file (rplidar by default, hokuyo with --launch hokuyo), reloads udev and enables the unit, and
# nothing is created (the prefix stays absent; /etc is never written: only dry runs here). Bad
# arguments and a missing build are refused. The unit itself: systemd-analyze verify (where it
# exists), its settings are those the plan writes to /etc/default/aslam, and its ExecStart, as
# systemd unescapes it, makes a run folder and starts aslam-procman deputy with them.
#   install_robot_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
install="$src/scripts/install-robot"
unit="$src/config/systemd/aslam-deputy.service"

source "$src/tests/check_lib.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# A stand-in build: the layout of a real one, each binary a script.
for binary in procman/aslam-procman tools/aslam-teleop tools/aslam-monitor slam/aslam-slam \
  drivers/kobuki/aslam-kobuki drivers/rplidar/aslam-rplidar drivers/hokuyo/aslam-hokuyo \
  eval/aslam; do
  mkdir -p "$tmp/build/$(dirname "$binary")"
  printf '#!/bin/sh\nexit 0\n' >"$tmp/build/$binary"
  chmod +x "$tmp/build/$binary"
done
mkdir -p "$tmp/build/tools/CMakeFiles"
before=$(find "$tmp" | sort)

"$install" --dry-run --prefix "$tmp/prefix" --build "$tmp/build" >"$tmp/plan.txt" 2>&1
rc=$?
cat "$tmp/plan.txt"
plan() { grep -qF -- "$1" "$tmp/plan.txt"; }
check "the dry run exits 0" test "$rc" -eq 0
check "it says it is a dry run" plan "dry run: nothing is changed"
check "binaries go under the prefix in the build's layout" \
  plan "$tmp/build/procman/aslam-procman $tmp/prefix/build/procman/aslam-procman"
check "... aslam-teleop among them" \
  grep -q "prefix/build/tools/aslam-teleop\$" "$tmp/plan.txt"
check "... aslam-kobuki too" grep -q "prefix/build/drivers/kobuki/aslam-kobuki\$" "$tmp/plan.txt"
check "... and linked from PREFIX/bin" \
  plan "ln -sfn ../build/tools/aslam-teleop $tmp/prefix/bin/aslam-teleop"
check "the udev rules are installed" \
  plan "config/udev/99-aslam.rules /etc/udev/rules.d/99-aslam.rules"
check "... and udev reloads them" plan "udevadm control --reload-rules"
check "... and applies them" plan "udevadm trigger"
check "the systemd unit is written" plan "write /etc/systemd/system/aslam-deputy.service"
check "... running the prefix's aslam-procman" plan "exec $tmp/prefix/bin/aslam-procman deputy"
check "... and enabled after a daemon-reload" \
  grep -qzE "systemctl daemon-reload.*systemctl enable aslam-deputy.service" "$tmp/plan.txt"
check "the launch file is the rplidar one" \
  plan "ASLAM_LAUNCH='$tmp/prefix/config/launch/robot_rplidar_kobuki.yaml'"
check "the bus reaches the laptop (ttl=1)" plan "ASLAM_LCM_URL='udpm://239.255.76.67:7667?ttl=1'"
check "the deputy's user is in group dialout" grep -qE "(useradd|usermod).*dialout" "$tmp/plan.txt"
after=$(find "$tmp" -path "$tmp/plan.txt" -prune -o -print | sort)
check "nothing was created or changed" test "$after" == "$before"

"$install" --dry-run --prefix "$tmp/prefix" --build "$tmp/build" --launch hokuyo \
  --link >"$tmp/hokuyo.txt" 2>&1
check "--launch hokuyo names the hokuyo launch file" \
  grep -qF "ASLAM_LAUNCH='$tmp/prefix/config/launch/robot_hokuyo_kobuki.yaml'" "$tmp/hokuyo.txt"
check "--link points PREFIX/build at the build folder" \
  grep -qF "ln -sfn $tmp/build $tmp/prefix/build" "$tmp/hokuyo.txt"

"$install" --dry-run --prefix "$tmp/prefix" --build "$tmp/build" --bogus >"$tmp/bad.txt" 2>&1
check "an unknown argument exits 2" test $? -eq 2
"$install" --dry-run --prefix "$tmp/prefix" --build "$tmp/nothing" >"$tmp/bad.txt" 2>&1
rc=$?
check "a missing build exits 1" test "$rc" -eq 1
check "... telling to build first" grep -q "scripts/build first" "$tmp/bad.txt"

# The unit.
if command -v systemd-analyze >/dev/null; then
  systemd-analyze verify "$unit" >"$tmp/verify.txt" 2>&1
  rc=$?
  cat "$tmp/verify.txt"
  check "systemd-analyze verify accepts the unit" test "$rc" -eq 0 -a ! -s "$tmp/verify.txt"
else
  echo "(systemd-analyze not installed: the unit is not verified)"
fi
# Every setting the plan writes to /etc/default/aslam is one the unit reads, and back.
written=$(sed -n "s/^ *\(ASLAM_[A-Z_]*\)=.*/\1/p" "$tmp/plan.txt" | sort -u | tr '\n' ' ')
read_by_unit=$(sed -n 's/^Environment="\{0,1\}\(ASLAM_[A-Z_]*\)=.*/\1/p' "$unit" |
  sort -u | tr '\n' ' ')
echo "written: $written; the unit's: $read_by_unit"
check "/etc/default/aslam sets exactly the unit's settings" test "$written" == "$read_by_unit"

# ExecStart as systemd unescapes it ($$ -> $, %% -> %), run with a stand-in aslam-procman.
script=$(sed -n "s/^ExecStart=\/bin\/sh -c '\(.*\)'\$/\1/p" "$unit" |
  sed -e 's/\$\$/$/g' -e 's/%%/%/g')
mkdir -p "$tmp/opt/bin"
printf '#!/bin/sh\nprintf "%%s\\n" "$@" >"%s"\n' "$tmp/argv.txt" >"$tmp/opt/bin/aslam-procman"
chmod +x "$tmp/opt/bin/aslam-procman"
script=${script//\/opt\/aslam/$tmp/opt}
ASLAM_RUNS_DIR="$tmp/runs" ASLAM_LAUNCH=/L.yaml ASLAM_LCM_URL='udpm://239.255.76.67:7667?ttl=1' \
  ASLAM_CONFIG=/C.yaml /bin/sh -c "$script"
check "ExecStart runs" test $? -eq 0
run_dir=$(readlink "$tmp/runs/latest")
echo "run folder: $run_dir; aslam-procman got: $(tr '\n' ' ' <"$tmp/argv.txt" 2>/dev/null)"
check "... making a run folder, linked as latest" test -d "$run_dir"
named_by_date() { [[ "$(basename "$run_dir")" =~ ^[0-9]{8}-[0-9]{6}$ ]]; }
check "... named by the date and time" named_by_date
expected="deputy --config /L.yaml --lcm-url udpm://239.255.76.67:7667?ttl=1"
expected+=" --log-dir $run_dir --vars CONFIG=/C.yaml "
check "... and starts the deputy on it" test "$(tr '\n' ' ' <"$tmp/argv.txt")" == "$expected"

echo "$passes passed, $failures failed"
exit $((failures > 0))
