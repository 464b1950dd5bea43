#pragma once

// `aslam bench`'s run scheduling: the world × method × seed matrix (per setting of a
// --set sweep, eval/bench_settings.h), which of its runs have finished (so an
// interrupted bench resumes where it stopped), and running the others on this machine
// (`--jobs`; a cluster's: eval/bench_slurm.h) as `aslam bench-task` children
// (eval/bench_run_list.h), J at a time, each writing its own run folder
// OUT/runs/<world>/<method>/seed_<NN>/ (with --set: OUT/runs/<setting>/<world>/...)
// with the child's output in explore.log.

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/pose2d.h"
#include "eval/bench_settings.h"

namespace aslam {

struct BenchOptions {
  std::vector<std::string> worlds;  // names under worlds/, world folders or MAP.yaml files
  std::vector<std::string> methods = {"fd", "ags", "ours", "ideal"};
  int seeds = 15;                  // seeds 1..seeds
  double duration_s = 1800.0;      // simulated seconds per run
  int jobs = 2;                    // runs in parallel
  std::optional<Pose2d> start;     // for every world (needed by a bare MAP.yaml)
  std::string config_file;         // passed to every run (with --set: the base of each setting's)
  std::vector<std::string> sweep;  // --set KEY=V1,V2,... in the order given; empty: no sweep
  std::string out_dir;
  std::string aslam_binary;  // the `aslam` executable that runs `explore --inproc`
  bool plots = true;         // call eval/bench_plots.py at the end
};

struct BenchRun {
  std::string world;        // as given (resolved path)
  std::string world_label;  // folder name or map file stem: runs/<label>/...
  std::string method;
  int seed = 0;
  std::string dir;          // run folder
  std::string setting;      // the setting's label; "" without --set
  std::string config_file;  // what the run reads: --config, or its setting's config.yaml
};

// One finished run's metrics.json, keys in file order; a nested object's keys as
// "outer.inner".
struct RunRecord {
  BenchRun run;
  std::vector<std::pair<std::string, std::string>> fields;  // raw JSON scalars ("null" kept)
  double Number(const std::string& key) const;              // NaN if missing or null
};

struct BenchProgress {
  int total = 0;
  int skipped = 0;   // finished before this invocation
  int finished = 0;  // finished by this invocation
  int failed = 0;
  int running = 0;
  int queued = 0;  // waiting for a cluster's resources (--slurm)
  double elapsed_s = 0.0;
  double eta_s = -1.0;  // < 0: unknown yet
};

// A run that ended without a finished metrics.json.
struct FailedRun {
  BenchRun run;
  std::string why;                // how it ended, e.g. "exit code 1"
  std::vector<std::string> logs;  // what to read: RUN/explore.log, and a Slurm task's log
};

struct BenchSummary {
  int total = 0;
  int skipped = 0;
  int finished = 0;
  std::vector<FailedRun> failed;
  bool interrupted = false;
  double wall_seconds = 0.0;
};

// "office" -> SOURCE/worlds/office when that exists and no such path does.
std::string ResolveWorld(const std::string& world);
// runs/<label> name of a world: its folder name or its MAP.yaml's stem.
std::string WorldLabel(const std::string& world);

// The run's folder under OUT/runs/, e.g. "office/fd/seed_01" or
// "utility.lambda=0.3/office/fd/seed_01": how messages name it.
std::string RunName(const BenchRun& run);

// The matrix in run order: seed by seed, each seed on every setting, world and
// method, so a partial matrix stays balanced across them. Throws
// std::invalid_argument for a bad option.
std::vector<BenchRun> PlanBench(const BenchOptions& options);

// The run folder's metrics.json parsed, if the run finished (any end reason
// but "interrupted").
std::optional<RunRecord> ReadFinishedRun(const BenchRun& run);

// Writes each setting's config (WriteSettingConfigs) and the unfinished runs' list to
// OUT/run_list.tsv (eval/bench_run_list.h), then runs each as an `aslam bench-task` child, J at
// a time; `stop` (Ctrl-C) stops the children and returns.
BenchSummary RunBench(const BenchOptions& options, const std::atomic<bool>* stop,
                      const std::function<void(const BenchProgress&)>& on_progress);

}  // namespace aslam
