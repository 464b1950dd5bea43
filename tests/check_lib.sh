# Sourced by the shell tests: `check NAME COMMAND...` runs the command and prints ok or
# FAILED with the name, counting `passes` and `failures`.
failures=0
passes=0
check() {
  local name="$1"
  shift
  if "$@"; then
    echo "ok: $name"
    passes=$((passes + 1))
  else
    echo "FAILED: $name"
    failures=$((failures + 1))
  fi
}
