#include "eval/bench_slurm.h"

#include <pwd.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "common/atomic_file.h"
#include "common/subprocess.h"
#include "common/text_format.h"
#include "eval/bench_run_list.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Slurm's default MaxArraySize: array task ids 0..1000.
constexpr int kDefaultMaxArraySize = 1001;
// squeue failing this many times in a row ends the waiting (the jobs keep running).
constexpr int kSqueueAttempts = 30;

std::string LastLine(const std::string& path) {
  std::istringstream in(ReadTextFile(path));
  std::string line, last;
  while (std::getline(in, line)) {
    if (!Trim(line).empty()) last = Trim(line);
  }
  return last;
}

std::string UserName() {
  const passwd* user = getpwuid(geteuid());
  return user ? user->pw_name : std::to_string(geteuid());
}

// Runs a Slurm command; a missing one is named with the package that has it.
CommandResult RunSlurmCommand(const std::vector<std::string>& argv) {
  try {
    return RunCommand(argv);
  } catch (const SpawnError& e) {
    throw std::runtime_error(std::string(e.what()) +
                             ": is Slurm's client (Debian: slurm-client) installed and on PATH?");
  }
}

// One array job: a submission folder and its runs in task order.
struct Submission {
  std::string dir;  // OUT/slurm/NNN
  std::string job_id;
  std::vector<std::string> run_dirs;  // absolute, by task id
};

std::string ScriptPath(const std::string& submission_dir) { return submission_dir + "/job.sbatch"; }

// Whether `queued` is task `task` (any task: -1) of the submission's job.
bool IsTaskOf(const SlurmQueuedTask& queued, const std::string& job_id,
              const std::string& submission_dir, int task) {
  return queued.job_id == job_id && queued.script == ScriptPath(submission_dir) &&
         (task < 0 || queued.task == task);
}

std::vector<Submission> EarlierSubmissions(const std::string& slurm_dir) {
  std::vector<Submission> submissions;
  if (!fs::is_directory(slurm_dir)) return submissions;
  for (const auto& entry : fs::directory_iterator(slurm_dir)) {
    const std::string dir = entry.path().string();
    const std::string job_id = Trim(ReadTextFile(dir + "/job_id"));
    if (job_id.empty()) continue;  // sbatch refused it
    Submission submission{dir, job_id, {}};
    try {
      for (const RunListEntry& run : ReadRunList(dir + "/run_list.tsv"))
        submission.run_dirs.push_back(run.dir);
    } catch (const std::runtime_error&) {
      continue;  // not one of ours
    }
    submissions.push_back(std::move(submission));
  }
  std::sort(submissions.begin(), submissions.end(),
            [](const Submission& a, const Submission& b) { return a.dir < b.dir; });
  return submissions;
}

// OUT/slurm/NNN, one past the highest NNN there.
std::string NextSubmissionDir(const std::string& slurm_dir) {
  int highest = 0;
  if (fs::is_directory(slurm_dir)) {
    for (const auto& entry : fs::directory_iterator(slurm_dir)) {
      const std::string name = entry.path().filename().string();
      if (name.find_first_not_of("0123456789") == std::string::npos && !name.empty())
        highest = std::max(highest, std::stoi(name));
    }
  }
  return slurm_dir + "/" + Format("%03d", highest + 1);
}

int MaxArraySize() {
  try {
    const CommandResult result = RunSlurmCommand({"scontrol", "show", "config"});
    if (result.status.success()) {
      if (const std::optional<int> size = ParseMaxArraySize(result.output)) return *size;
    }
  } catch (const std::runtime_error&) {
  }
  return kDefaultMaxArraySize;
}

// Writes the submission's run list and script, then sbatch; returns the job id.
std::string Submit(const SlurmOptions& slurm, const std::string& aslam_binary,
                   const std::string& dir, const std::vector<RunListEntry>& runs) {
  fs::create_directories(dir);
  const std::string run_list = dir + "/run_list.tsv";
  WriteRunList(run_list, runs);
  const std::string script = ScriptPath(dir);
  WriteFileAtomically(script,
                      SlurmJobScript(slurm, aslam_binary, run_list, static_cast<int>(runs.size())));
  std::vector<std::string> argv = {"sbatch", "--parsable", "--chdir=" + dir,
                                   "--output=" + dir + "/task_%a.log", "--open-mode=append"};
  argv.insert(argv.end(), slurm.sbatch_args.begin(), slurm.sbatch_args.end());
  argv.push_back(script);
  WriteFileAtomically(dir + "/sbatch.txt", ShellCommandLine(argv) + "\n");
  const CommandResult result = RunSlurmCommand(argv);
  const std::optional<std::string> job_id = ParseSbatchJobId(result.output);
  if (!result.status.success() || !job_id) {
    throw std::runtime_error("sbatch refused " + script + " (" + result.status.Describe() +
                             "): " + Trim(result.output));
  }
  WriteFileAtomically(dir + "/job_id", *job_id + "\n");
  return *job_id;
}

// A run this invocation waits for.
struct TrackedRun {
  const BenchRun* run = nullptr;
  std::string job_id;
  int task = 0;
  std::string submission_dir;
  int polls_unqueued = 0;  // successive polls that found its task gone without a finished run
  bool done = false;
};

}  // namespace

void CheckSlurmOptions(const SlurmOptions& slurm) {
  const std::vector<std::pair<const char*, std::string>> values = {
      {"--partition", slurm.partition}, {"--time", slurm.time_limit}, {"--mem", slurm.memory}};
  for (const auto& [flag, value] : values) {
    if (value.find_first_of(" \t\r\n#'\"\\") != std::string::npos) {
      throw std::invalid_argument(std::string(flag) + " '" + value +
                                  "': must be one word (no spaces, quotes or '#')");
    }
  }
  for (const std::string& arg : slurm.sbatch_args) {
    if (arg.rfind('-', 0) != 0)
      throw std::invalid_argument("--sbatch_args: '" + arg + "' is not an option (-X or --name=V)");
  }
  if (slurm.max_running < 0)
    throw std::invalid_argument("--jobs with --slurm must be >= 0 (0: no limit)");
  if (!(slurm.poll_s > 0.0) || !std::isfinite(slurm.poll_s))
    throw std::invalid_argument(
        Format("--slurm_poll_s %g: must be a number of seconds > 0", slurm.poll_s));
}

std::string SlurmArraySpec(int count, int max_running) {
  std::string spec = count <= 1 ? "0" : "0-" + std::to_string(count - 1);
  if (max_running > 0) spec += "%" + std::to_string(max_running);
  return spec;
}

std::string SlurmJobScript(const SlurmOptions& slurm, const std::string& aslam_binary,
                           const std::string& run_list, int count) {
  std::string script = "#!/bin/bash\n";
  script += Format("# aslam bench: %d runs, one per array task; written by `aslam bench --slurm`\n",
                   count);
  script += "#SBATCH --job-name=aslam-bench\n";
  script += "#SBATCH --array=" + SlurmArraySpec(count, slurm.max_running) + "\n";
  script += "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n";
  if (!slurm.partition.empty()) script += "#SBATCH --partition=" + slurm.partition + "\n";
  if (!slurm.time_limit.empty()) script += "#SBATCH --time=" + slurm.time_limit + "\n";
  if (!slurm.memory.empty()) script += "#SBATCH --mem=" + slurm.memory + "\n";
  script += ShellQuoted(aslam_binary) + " bench-task " + ShellQuoted(run_list) +
            " \"$SLURM_ARRAY_TASK_ID\"\n";
  script += "status=$?\n";
  script +=
      "echo \"aslam bench: task $SLURM_ARRAY_TASK_ID ended with exit status $status on "
      "$(hostname) at $(date -u +%Y-%m-%dT%H:%M:%SZ)\"\n";
  script += "exit \"$status\"\n";
  return script;
}

std::optional<std::string> ParseSbatchJobId(const std::string& output) {
  std::istringstream in(output);
  std::string line;
  std::optional<std::string> id;
  while (std::getline(in, line)) {
    const std::string word = Trim(line.substr(0, line.find(';')));
    if (!word.empty() && word.find_first_not_of("0123456789") == std::string::npos) id = word;
  }
  return id;
}

std::optional<int> ParseMaxArraySize(const std::string& output) {
  std::istringstream in(output);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t equals = line.find('=');
    if (equals == std::string::npos || Trim(line.substr(0, equals)) != "MaxArraySize") continue;
    const std::string value = Trim(line.substr(equals + 1));
    char* end = nullptr;
    const long size = std::strtol(value.c_str(), &end, 10);
    if (!value.empty() && *end == '\0' && size > 0) return static_cast<int>(size);
  }
  return std::nullopt;
}

std::vector<SlurmQueuedTask> ParseSqueueTasks(const std::string& output) {
  std::vector<SlurmQueuedTask> tasks;
  std::istringstream in(output);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t a = line.find('|');
    const std::size_t b = a == std::string::npos ? a : line.find('|', a + 1);
    const std::size_t c = b == std::string::npos ? b : line.find('|', b + 1);
    if (c == std::string::npos) continue;
    const std::string job = Trim(line.substr(0, a));
    const std::string task = Trim(line.substr(a + 1, b - a - 1));
    if (job.empty() || task.empty() || job.find_first_not_of("0123456789") != std::string::npos ||
        task.find_first_not_of("0123456789") != std::string::npos) {
      continue;
    }
    // The script is the rest of the line: a path may hold a '|'.
    tasks.push_back(
        {job, std::stoi(task), Trim(line.substr(b + 1, c - b - 1)), Trim(line.substr(c + 1))});
  }
  return tasks;
}

BenchSummary RunSlurmBench(const BenchOptions& options, const SlurmOptions& slurm,
                           const std::atomic<bool>* stop,
                           const std::function<void(const BenchProgress&)>& on_progress,
                           const std::function<void(const std::string&)>& on_message) {
  CheckSlurmOptions(slurm);
  const std::vector<BenchRun> runs = PlanBench(options);
  if (options.aslam_binary.empty()) throw std::invalid_argument("RunSlurmBench: no aslam binary");
  WriteSettingConfigs(options.config_file, PlanSettings(options.sweep), options.out_dir);
  const Clock::time_point start = Clock::now();
  const std::string slurm_dir =
      fs::absolute(options.out_dir).lexically_normal().string() + "/slurm";
  auto message = [&](const std::string& text) {
    if (on_message) on_message(text);
  };

  // Which tasks the queue holds now; nullopt when squeue failed (said through on_message).
  int squeue_failures = 0;
  auto queued_tasks = [&]() -> std::optional<std::vector<SlurmQueuedTask>> {
    const CommandResult result = RunSlurmCommand(
        {"squeue", "--noheader", "--array", "--user=" + UserName(), "--format=%F|%K|%T|%o"});
    if (result.status.success()) {
      squeue_failures = 0;
      return ParseSqueueTasks(result.output);
    }
    if (++squeue_failures >= kSqueueAttempts) {
      throw std::runtime_error(Format(
          "squeue failed %d times in a row (%s): %s; the array jobs may still run: rerun the "
          "same command to wait for them",
          squeue_failures, result.status.Describe().c_str(), Trim(result.output).c_str()));
    }
    message("squeue failed (" + result.status.Describe() + "): " + Trim(result.output) +
            "; trying again");
    return std::nullopt;
  };

  BenchSummary summary;
  summary.total = static_cast<int>(runs.size());
  std::vector<TrackedRun> tracked;

  // Runs in a job of an earlier invocation that is still queued are waited for, not resubmitted.
  std::vector<SlurmQueuedTask> queue;
  std::vector<Submission> earlier = EarlierSubmissions(slurm_dir);
  if (!earlier.empty()) {
    std::optional<std::vector<SlurmQueuedTask>> now;
    while (!(now = queued_tasks())) std::this_thread::sleep_for(std::chrono::duration<double>(1));
    queue = *now;
  }
  std::map<std::string, std::pair<const Submission*, int>> in_flight;  // run dir -> job, task
  for (const Submission& submission : earlier) {
    const bool queued = std::any_of(queue.begin(), queue.end(), [&](const SlurmQueuedTask& t) {
      return IsTaskOf(t, submission.job_id, submission.dir, -1);
    });
    if (!queued) continue;
    message("waiting for array job " + submission.job_id + " of an earlier invocation (" +
            submission.dir + ")");
    for (std::size_t task = 0; task < submission.run_dirs.size(); ++task)
      in_flight[submission.run_dirs[task]] = {&submission, static_cast<int>(task)};
  }

  std::vector<const BenchRun*> to_submit;
  for (const BenchRun& run : runs) {
    if (ReadFinishedRun(run)) {
      ++summary.skipped;
      continue;
    }
    const auto flight = in_flight.find(MakeRunListEntry(options, run).dir);
    if (flight != in_flight.end()) {
      tracked.push_back(
          {&run, flight->second.first->job_id, flight->second.second, flight->second.first->dir});
    } else {
      to_submit.push_back(&run);
    }
  }

  if (!to_submit.empty()) {
    const int per_job = MaxArraySize();
    for (std::size_t first = 0; first < to_submit.size(); first += per_job) {
      const std::size_t last = std::min(to_submit.size(), first + per_job);
      std::vector<RunListEntry> entries;
      for (std::size_t i = first; i < last; ++i)
        entries.push_back(MakeRunListEntry(options, *to_submit[i]));
      const std::string dir = NextSubmissionDir(slurm_dir);
      const std::string job_id = Submit(slurm, options.aslam_binary, dir, entries);
      message(Format("submitted array job %s: %zu runs (%s)", job_id.c_str(), last - first,
                     dir.c_str()));
      for (std::size_t i = first; i < last; ++i)
        tracked.push_back({to_submit[i], job_id, static_cast<int>(i - first), dir});
    }
  }
  if (!slurm.wait) {
    summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return summary;
  }

  std::vector<double> run_wall_s;
  // A progress line when the counts change, else once a minute: polls can be many.
  std::vector<int> last_counts;
  Clock::time_point last_report;
  auto report = [&](int running, int queued) {
    if (!on_progress) return;
    const std::vector<int> counts = {summary.finished, static_cast<int>(summary.failed.size()),
                                     running, queued};
    if (counts == last_counts && Clock::now() - last_report < std::chrono::seconds(60)) return;
    last_counts = counts;
    last_report = Clock::now();
    BenchProgress p;
    p.total = summary.total;
    p.skipped = summary.skipped;
    p.finished = summary.finished;
    p.failed = static_cast<int>(summary.failed.size());
    p.running = running;
    p.queued = queued;
    p.elapsed_s = std::chrono::duration<double>(Clock::now() - start).count();
    if (!run_wall_s.empty() && running > 0) {
      double mean = 0.0;
      for (const double w : run_wall_s) mean += w;
      mean /= run_wall_s.size();
      p.eta_s = (queued + 0.5 * running) * mean / running;
    }
    on_progress(p);
  };

  std::set<std::string> waited_jobs;
  for (const TrackedRun& t : tracked) waited_jobs.insert(t.job_id);
  while (true) {
    if (stop && stop->load()) {
      summary.interrupted = true;
      std::string jobs;
      for (const std::string& id : waited_jobs) jobs += " " + id;
      message(
          "stopped waiting; the array jobs keep running: rerun the same command to wait for "
          "them again, or `scancel" +
          jobs + "` to stop them");
      break;
    }
    const std::optional<std::vector<SlurmQueuedTask>> now = queued_tasks();
    int running = 0, queued = 0, open = 0;
    for (TrackedRun& t : tracked) {
      if (t.done) continue;
      if (const std::optional<RunRecord> record = ReadFinishedRun(*t.run)) {
        t.done = true;
        ++summary.finished;
        const double wall_s = record->Number("wall_seconds");
        if (std::isfinite(wall_s)) run_wall_s.push_back(wall_s);
        continue;
      }
      ++open;
      if (!now) continue;
      const auto task = std::find_if(now->begin(), now->end(), [&](const SlurmQueuedTask& q) {
        return IsTaskOf(q, t.job_id, t.submission_dir, t.task);
      });
      if (task != now->end()) {
        t.polls_unqueued = 0;
        (task->state == "PENDING" || task->state == "CONFIGURING" ? queued : running) += 1;
        continue;
      }
      // Gone from the queue without a finished run; a second look allows for a shared
      // filesystem's delay in showing this host the run's last files.
      if (++t.polls_unqueued < 2) continue;
      t.done = true;
      --open;
      const std::string task_log = Format("%s/task_%d.log", t.submission_dir.c_str(), t.task);
      std::string why = LastLine(task_log);
      if (why.empty()) why = "its task left no log";
      summary.failed.push_back(
          {*t.run,
           "array job " + t.job_id + " task " + std::to_string(t.task) + ": " + why,
           {task_log, t.run->dir + "/explore.log"}});
    }
    report(running, queued);
    if (open == 0) break;
    const Clock::time_point poll_end =
        Clock::now() +
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(slurm.poll_s));
    while (Clock::now() < poll_end && !(stop && stop->load()))
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return summary;
}

}  // namespace aslam
