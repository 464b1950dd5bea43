#!/usr/bin/env bash
# `aslam bench --slurm` on a one-node Slurm cluster of its own (scripts/slurm-one-node: munged,
# slurmctld and slurmd from Debian's packages with a generated slurm.conf in a temporary folder,
# in a network namespace of their own). A 3-run bench through it reports the same as with
# --jobs 2; a rerun submits only the missing and failed runs and names the failure and its task
# log; a bench submitted with --no_wait is waited for by a rerun (Ctrl-C stops the waiting, not
# the job), not submitted twice. The cluster is torn down at the end. Exits 77 (skipped) without
# root or the packages (scripts/install-deps --slurm).
#   slurm_bench_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1"
build="$2"
# The cluster: scripts/slurm-one-node runs this script again inside it (77 where it cannot).
[[ -n "${SLURM_CONF:-}" && -n "${ASLAM_SLURM_ONE_NODE_NETNS:-}" ]] ||
  exec "$src/scripts/slurm-one-node" "$0" "$@"
source "$src/tests/check_lib.sh"
node=$(hostname -s)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

aslam="$build/eval/aslam"
bench=("$aslam" bench --worlds test --methods fd,ags,ours --seeds 1 --duration 40
  --config "$src/config/aslam.yaml" --noplots)
# The reports agree: the tables and curves as they are, runs.csv but for the run folder, wall and
# CPU time (the only columns that differ between two runs of one seed).
same_reports() {
  local a="$1" b="$2" file
  for file in table1.md table2.md coverage.md comparison.md goals.md curves.csv; do
    cmp "$a/$file" "$b/$file" || return 1
  done
  python3 - "$a/runs.csv" "$b/runs.csv" <<'EOF'
import csv, re, sys
def rows(path):
    table = list(csv.reader(open(path)))
    keep = [i for i, name in enumerate(table[0])
            if not re.match(r"run_dir$|wall_seconds$|sim_per_cpu|node_cpu_s\.", name)]
    return [[row[i] for i in keep] for row in table]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
if a != b or len(a) != 4:
    sys.exit(f"runs.csv differ or do not hold 3 runs:\n{a}\n{b}")
EOF
}
count_lines() { grep -c "$1" "$2" 2>/dev/null || true; }
# run_bench NAME ARGS...: the bench with ARGS, its output in $out/NAME.txt and shown; rc its status.
run_bench() {
  local name="$1"
  shift
  "${bench[@]}" "$@" >"$out/$name.txt" 2>&1
  rc=$?
  cat "$out/$name.txt"
}

"${bench[@]}" --jobs 2 --out "$out/local" >"$out/local.txt" 2>&1
check "the bench with --jobs 2 finishes its 3 runs" test $? -eq 0
run_bench cluster --slurm --slurm_poll_s 0.5 --out "$out/cluster"
check "the bench with --slurm exits 0" test "$rc" -eq 0
check "... submitting one array job of 3 runs" \
  test "$(count_lines 'submitted array job [0-9]*: 3 runs' "$out/cluster.txt")" -eq 1
check "... whose run list holds the 3 runs" \
  test "$(grep -c "^$out/cluster/runs/test/" "$out/cluster/slurm/001/run_list.tsv")" -eq 3
check "... and each task's log names its host and exit status 0" \
  test "$(cat "$out"/cluster/slurm/001/task_*.log | count_lines "ended with exit status 0 on $node" -)" -eq 3
check "the report equals the --jobs 2 bench's" same_reports "$out/local" "$out/cluster"

# A rerun submits only what is missing or failed: ags' metrics.json gone, ours' run made to fail
# (its explore.log is a folder: the task cannot write it).
rm "$out/cluster/runs/test/ags/seed_01/metrics.json" "$out/cluster/runs/test/ours/seed_01/metrics.json"
mv "$out/cluster/runs/test/ours/seed_01/explore.log" "$out/ours_explore.log"
mkdir "$out/cluster/runs/test/ours/seed_01/explore.log"
run_bench rerun --slurm --slurm_poll_s 0.5 --out "$out/cluster"
check "a rerun with a failing run exits 1" test "$rc" -eq 1
check "... submitting the 2 unfinished runs only" \
  test "$(count_lines 'submitted array job [0-9]*: 2 runs' "$out/rerun.txt")" -eq 1
check "... reruns ags" test -s "$out/cluster/runs/test/ags/seed_01/metrics.json"
check "... names the failed run, its task and both logs" grep -q \
  "run failed: test/ours/seed_01: array job [0-9]* task 1: aslam bench: task 1 ended with exit status 1 .*; see $out/cluster/slurm/002/task_1.log, $out/cluster/runs/test/ours/seed_01/explore.log" \
  "$out/rerun.txt"
check "... whose task log says why" grep -q "explore.log: Is a directory" \
  "$out/cluster/slurm/002/task_1.log"

# --no_wait submits and returns; a rerun while the job is queued (its partition down) waits for
# that job instead of submitting the run again.
rmdir "$out/cluster/runs/test/ours/seed_01/explore.log"
scontrol update PartitionName=local State=DOWN
run_bench no_wait --slurm --no_wait --out "$out/cluster"
check "--no_wait exits 0 at once" test "$rc" -eq 0
check "... having submitted the failed run" \
  test "$(count_lines 'submitted array job [0-9]*: 1 runs' "$out/no_wait.txt")" -eq 1
job=$(cat "$out/cluster/slurm/003/job_id")
check "... which is queued" test "$(squeue --noheader --jobs="$job" --format=%T)" == PENDING
# waiting_for NAME: until $out/NAME.txt says the bench waits for $job (10 s at most).
waiting_for() {
  for _ in $(seq 50); do
    grep -q "waiting for array job $job" "$out/$1.txt" && return 0
    sleep 0.2
  done
  return 1
}
# Ctrl-C stops the waiting, not the job.
"${bench[@]}" --slurm --slurm_poll_s 0.5 --out "$out/cluster" >"$out/interrupted.txt" 2>&1 &
waiter=$!
waiting_for interrupted
kill -INT "$waiter"
wait "$waiter"
rc=$?
cat "$out/interrupted.txt"
check "Ctrl-C while waiting exits 130" test "$rc" -eq 130
check "... saying the job keeps running and how to stop it" \
  grep -q "stopped waiting; the array jobs keep running: .*scancel $job" "$out/interrupted.txt"
check "... and it is still queued" test "$(squeue --noheader --jobs="$job" --format=%T)" == PENDING
"${bench[@]}" --slurm --slurm_poll_s 0.5 --out "$out/cluster" >"$out/attach.txt" 2>&1 &
attached=$!
waiting_for attach
scontrol update PartitionName=local State=UP
wait "$attached"
rc=$?
cat "$out/attach.txt"
check "the rerun waits for job $job and exits 0" test "$rc" -eq 0
check "... without submitting anything" test "$(count_lines 'submitted' "$out/attach.txt")" -eq 0
check "... says it waits for the earlier job" grep -q "waiting for array job $job of an earlier" \
  "$out/attach.txt"
check "no fourth submission" test ! -e "$out/cluster/slurm/004"
check "the report equals the --jobs 2 bench's again" same_reports "$out/local" "$out/cluster"
"${bench[@]}" --slurm --report_only --out "$out/cluster" >"$out/report_only.txt" 2>&1
check "--report_only writes the reports without submitting" \
  test "$(count_lines 'submitted' "$out/report_only.txt")" -eq 0
check "... counting the finished runs" grep -q "3 of 3 runs finished$" "$out/report_only.txt"
check "... and they are the same" same_reports "$out/local" "$out/cluster"

echo "$passes passed, $failures failed"
((failures == 0))
