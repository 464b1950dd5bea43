# Sourced by the *_process_test.sh scripts after they set `src`, `build` and
# `port_base`: re-runs the script in a private network namespace when user
# namespaces allow (else it stays on a port of its own with ttl=0; and so when
# the script set `stay_in_this_namespace=1`), and provides `url`, `out` (a
# temporary folder), `check` and `heard`.

if [[ -z "${ASLAM_IN_NETNS:-}" && -z "${stay_in_this_namespace:-}" ]] &&
  unshare -rn true 2>/dev/null; then
  ASLAM_IN_NETNS=1 exec "$src/scripts/in-private-netns" "$0" "$@"
fi

url="udpm://239.255.76.67:$((port_base + $$ % 100))?ttl=0"
monitor="$build/tools/aslam-monitor"
source "$src/tests/check_lib.sh"

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

heard() {  # heard CHANNEL TYPE MIN: the monitor's last table has at least MIN messages
  awk -v c="$1" -v t="$2" -v min="$3" '$1 == c && $2 == t { n = $3 } END { exit !(n >= min) }' \
    "$out/monitor.txt"
}
