#pragma once

// `aslam bench --slurm`: the bench's unfinished runs as a Slurm array job, one task per run, each
// task `aslam bench-task LIST N` (eval/bench_run_list.h, the same entry point as --jobs) writing
// its run folder under OUT on a filesystem every node shares.
//
// OUT/slurm/NNN/ is one submission: run_list.tsv (its runs), job.sbatch (the script), sbatch.txt
// (the command), job_id (once sbatch accepted it) and task_<N>.log (each task's own log: which
// run, which host, its exit status, or Slurm's word on a time limit). A cluster's MaxArraySize
// splits a larger bench into several submissions.
//
// The bench then waits: it counts the runs' finished metrics.json and asks squeue which tasks
// are queued or running; a task that left the queue without a finished run has failed. Ctrl-C
// stops the waiting, not the jobs. Rerunning the same command waits for the jobs of an earlier
// invocation still in the queue, and submits only the runs that are neither finished nor in one.

#include <atomic>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "eval/bench_runs.h"

namespace aslam {

struct SlurmOptions {
  std::string partition;                 // sbatch --partition; "" = the cluster's default
  std::string time_limit;                // sbatch --time per task, e.g. 30 or 1:00:00; "" = default
  std::string memory;                    // sbatch --mem per task, e.g. 2G; "" = default
  int max_running = 0;                   // tasks at a time (the array's %N); 0 = as many as fit
  std::vector<std::string> sbatch_args;  // more sbatch options, e.g. --account=lab
  bool wait = true;                      // wait for the jobs, then write the reports
  double poll_s = 30.0;  // between squeue calls while waiting (a cluster's courtesy)
};

// Throws std::invalid_argument naming the option: a value with whitespace or a '#', a negative
// max_running, poll_s not > 0.
void CheckSlurmOptions(const SlurmOptions& slurm);

// sbatch's --array value for `count` tasks: "0-4", "0-4%2" with max_running 2, "0" for one.
std::string SlurmArraySpec(int count, int max_running);

// The batch script of one submission: #SBATCH lines for the job name, the array, partition, time
// and memory, then `aslam bench-task LIST $SLURM_ARRAY_TASK_ID` and its exit status.
std::string SlurmJobScript(const SlurmOptions& slurm, const std::string& aslam_binary,
                           const std::string& run_list, int count);

// The job id in `sbatch --parsable`'s output ("123" or "123;cluster", maybe after warnings).
std::optional<std::string> ParseSbatchJobId(const std::string& output);

// `scontrol show config`'s MaxArraySize; nullopt when the text has none.
std::optional<int> ParseMaxArraySize(const std::string& output);

// A task still in the queue, from `squeue --array --format=%F|%K|%T|%o`: array job id, task id,
// state (PENDING, RUNNING, COMPLETING, ...) and the batch script, which tells a bench's job from
// another of the same id (a restarted controller numbers jobs from 1 again).
struct SlurmQueuedTask {
  std::string job_id;
  int task = 0;
  std::string state;
  std::string script;
};
// Lines that are not of that form (a plain job's N/A task) are left out.
std::vector<SlurmQueuedTask> ParseSqueueTasks(const std::string& output);

// Runs the bench's unfinished runs on Slurm, waits for them (unless !slurm.wait) and returns what
// happened, like RunBench. Throws std::runtime_error when sbatch refuses a submission (its output
// quoted) or squeue keeps failing.
BenchSummary RunSlurmBench(const BenchOptions& options, const SlurmOptions& slurm,
                           const std::atomic<bool>* stop,
                           const std::function<void(const BenchProgress&)>& on_progress,
                           const std::function<void(const std::string&)>& on_message);

}  // namespace aslam
