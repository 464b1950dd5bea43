#!/usr/bin/env bash
# SLAM_MAP over a lossy network. In a private network namespace whose loopback drops a
# fraction of all UDP packets at random (nftables numgen: the same as tc netem loss, which
# kernels without sch_netem lack), lcm-logplayer plays COUNT maps of MAP to lcm-logger over
# udpm, once in the wire type SLAM publishes (zlib) and once as the legacy raw grid. The
# compressed maps must arrive at >= 95 %, and nftables must have dropped packets (else the
# check proved nothing); the raw ones are reported.
#   map_over_lossy_network_test.sh SRC BUILD [LOSS_PERCENT [MTU [MAP.yaml|RUN.lcmlog [COUNT]]]]
# Given a run's lcm log instead of a map, plays that run's own SLAM_MAP messages.
# MTU 1500 shows a Wi-Fi link, where a datagram bigger than one frame is IP-fragmented and
# any lost fragment loses it. Exits 77 (skipped) without nft or unprivileged namespaces.
set -euo pipefail
export PATH=$PATH:/usr/sbin:/sbin  # nft and ip, for a user whose PATH lacks them
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
loss_percent=${3:-1}
mtu=${4:-65536}
map=${5:-$src/worlds/office/map.yaml}
count=${6:-300}

if [[ -z ${ASLAM_IN_LOSSY_NETNS:-} ]]; then
  command -v nft >/dev/null || { echo "SKIPPED: nft (Debian package nftables) is not installed"; exit 77; }
  unshare -rn true 2>/dev/null || { echo "SKIPPED: unshare -rn is not permitted here"; exit 77; }
  ASLAM_IN_LOSSY_NETNS=1 exec unshare -rn "$0" "$@"
fi

ip link set lo up
ip link set lo mtu "$mtu"
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
per_10000=$(awk -v p="$loss_percent" 'BEGIN { printf "%d", p * 100 + 0.5 }')
# On ingress, after IP fragmentation: each frame is lost on its own, as with netem.
nft add table netdev lossy
nft add chain netdev lossy in '{ type filter hook ingress device lo priority 0; }'
nft add rule netdev lossy in ip protocol udp numgen random mod 10000 \< "$per_10000" counter drop

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
url="udpm://239.255.76.67:7690?ttl=0"

# SLAM_MAP messages in a log, from aslam log-stats's channel table (field 2: messages,
# field 4: the largest in kB).
map_field() {
  "$build/eval/aslam" log-stats "$1" | awk -v f="$2" '$1 == "SLAM_MAP" { v = $f } END { print v + 0 }'
}

# Plays the SLAM_MAP messages of a log to lcm-logger; prints "PLAYED ARRIVED".
play() {
  local log=$1 heard="$work/heard.lcmlog"
  lcm-logger --lcm-url="$url" --quiet --force "$heard" >/dev/null &
  local logger=$!
  sleep 1
  lcm-logplayer --lcm-url="$url" --regexp='^SLAM_MAP$' "$log" >/dev/null
  sleep 1
  kill -INT "$logger"
  wait "$logger" || true
  echo "$(map_field "$log" 2) $( [[ -s $heard ]] && map_field "$heard" 2 || echo 0)"
}

percent() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", (b > 0 ? 100 * a / b : 0) }'; }
dropped() {
  nft list ruleset | awk '/counter packets/ { for (i = 1; i < NF; ++i) if ($i == "packets") print $(i + 1) }'
}

if [[ $map == *.lcmlog ]]; then  # a recorded run: its own maps, as SLAM published them
  read -r sent heard < <(play "$map")
  echo "loss ${loss_percent} % of UDP frames, MTU $mtu, $map: $(dropped) frames dropped"
  echo "$heard of $sent maps arrived ($(percent "$heard" "$sent") %), largest $(map_field "$map" 4) kB"
  ((heard * 100 >= sent * 95)) || { echo "FAIL: fewer than 95 % of the maps arrived"; exit 1; }
  exit 0
fi

"$build/tests/write_map_log" "$map" zlib "$count" 50 "$work/zlib.lcmlog"
"$build/tests/write_map_log" "$map" raw "$count" 50 "$work/raw.lcmlog"
read -r zlib_sent zlib_heard < <(play "$work/zlib.lcmlog")
read -r raw_sent raw_heard < <(play "$work/raw.lcmlog")
dropped=$(dropped)
echo "loss ${loss_percent} % of UDP frames, MTU $mtu, map $(basename "$(dirname "$map")")/$(basename "$map"): $dropped frames dropped"
echo "zlib: $zlib_heard of $zlib_sent maps arrived ($(percent "$zlib_heard" "$zlib_sent") %), $(map_field "$work/zlib.lcmlog" 4) kB each"
echo "raw:  $raw_heard of $raw_sent maps arrived ($(percent "$raw_heard" "$raw_sent") %), $(map_field "$work/raw.lcmlog" 4) kB each"

status=0
if ((zlib_sent != count || raw_sent != count)); then
  echo "FAIL: the logs to play hold $zlib_sent and $raw_sent maps, not $count"; status=1
fi
if ((zlib_heard * 100 < zlib_sent * 95)); then
  echo "FAIL: fewer than 95 % of the compressed maps arrived"; status=1
fi
if ((${dropped:-0} == 0)) && [[ $loss_percent != 0 ]]; then
  echo "FAIL: nftables dropped no packet: the link was not lossy and the check proved nothing"; status=1
fi
exit "$status"
