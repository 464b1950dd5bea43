#pragma once

// `aslam bench`: the paper's experiment (Tables I and II, Figs. 3–5) as one
// command. Runs the world × method × seed matrix in-process, each run an
// `aslam explore --inproc` child process writing its own run folder, J at a
// time; a run whose folder holds a finished metrics.json is skipped, so an
// interrupted bench resumes where it stopped. Then aggregates every finished
// run into the reports and figures (matplotlib, eval/bench_plots.py).
//
// Layout of OUT: runs/<world>/<method>/seed_<NN>/ (run folders, with the
// child's output in explore.log), runs.csv, table1.md, table2.md,
// coverage.md, comparison.md, curves.csv, fig3.png, fig4.png,
// fig5_<world>.png (+ fig5_<world>_*.{png,csv} inputs of that figure),
// bench.log (the plotting tool's output).

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/pose2d.h"

namespace aslam {

struct BenchOptions {
  std::vector<std::string> worlds;   // names under worlds/, world folders or MAP.yaml files
  std::vector<std::string> methods = {"fd", "ags", "ours"};
  int seeds = 15;                    // seeds 1..seeds
  double duration_s = 1800.0;        // simulated seconds per run
  int jobs = 2;                      // runs in parallel
  std::optional<Pose2d> start;       // for every world (needed by a bare MAP.yaml)
  std::string config_file;           // passed to every run
  std::string out_dir;
  std::string aslam_binary;          // the `aslam` executable that runs `explore --inproc`
  bool plots = true;                 // call eval/bench_plots.py at the end
};

struct BenchRun {
  std::string world;        // as given (resolved path)
  std::string world_label;  // folder name or map file stem: runs/<label>/...
  std::string method;
  int seed = 0;
  std::string dir;          // run folder
};

// One finished run's metrics.json, keys in file order.
struct RunRecord {
  BenchRun run;
  std::vector<std::pair<std::string, std::string>> fields;  // raw JSON scalars ("null" kept)
  double Number(const std::string& key) const;              // NaN if missing or null
};

struct BenchProgress {
  int total = 0;
  int skipped = 0;    // finished before this invocation
  int finished = 0;   // finished by this invocation
  int failed = 0;
  int running = 0;
  double elapsed_s = 0.0;
  double eta_s = -1.0;  // < 0: unknown yet
};

struct BenchSummary {
  int total = 0;
  int skipped = 0;
  int finished = 0;
  std::vector<std::string> failed;  // run folders whose child exited non-zero
  bool interrupted = false;
  double wall_seconds = 0.0;
};

// The method the others are compared with: "ours" when it ran, else the last.
std::string ReferenceMethod(const std::vector<std::string>& methods);

// "office" -> SOURCE/worlds/office when that exists and no such path does.
std::string ResolveWorld(const std::string& world);
// runs/<label> name of a world: its folder name or its MAP.yaml's stem.
std::string WorldLabel(const std::string& world);

// The matrix in run order: seed by seed, each seed on every world with every
// method, so a partial matrix stays balanced across worlds and methods. Throws std::invalid_argument for a bad option.
std::vector<BenchRun> PlanBench(const BenchOptions& options);

// The run folder's metrics.json parsed, if the run finished (any end reason
// but "interrupted").
std::optional<RunRecord> ReadFinishedRun(const BenchRun& run);

// Runs every unfinished run; `stop` (Ctrl-C) stops the children and returns.
BenchSummary RunBench(const BenchOptions& options, const std::atomic<bool>* stop,
                      const std::function<void(const BenchProgress&)>& on_progress);

// mean and sample standard deviation (n − 1) of the finite values; NaN if none
// (std 0 for one value).
struct MeanStd {
  double mean = 0.0;
  double std = 0.0;
  int n = 0;
};
MeanStd ComputeMeanStd(const std::vector<double>& values);

// Two-sided Mann–Whitney U test of a against b: the normal approximation with
// tie and continuity corrections. NaN values are dropped and +inf ranks last;
// NaN if either sample is empty.
double MannWhitneyP(const std::vector<double>& a, const std::vector<double>& b);

// Per (world, method) and per simulated second: mean ± std of coverage and of
// mean edge D-optimality over the runs. A run that ended early (done) holds
// its last value to the end.
struct CurvePoint {
  double t_s = 0.0;
  MeanStd coverage;
  MeanStd d_opt;
};
std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>> ComputeCurves(
    const std::vector<RunRecord>& records, double duration_s);

// The reports' text.
std::string RunsCsv(const std::vector<RunRecord>& records);
std::string Table1Markdown(const std::vector<RunRecord>& records, const std::vector<std::string>& worlds,
                           const std::vector<std::string>& methods);
std::string Table2Markdown(const std::vector<RunRecord>& records,
                           const std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>>& curves,
                           const std::vector<std::string>& worlds, const std::vector<std::string>& methods);
std::string CurvesCsv(const std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>>& curves);
// Coverage % (mean ± std) at 1/6, 1/3, 2/3 and all of the duration (5, 10, 20
// and 30 min of the paper's 30), and the median time to 90 % coverage over all
// runs, a run that never reached 90 % counting as later than every run that did.
std::string CoverageMarkdown(const std::vector<RunRecord>& records,
                             const std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>>& curves,
                             const std::vector<std::string>& worlds, const std::vector<std::string>& methods,
                             double duration_s);
// Per world and metric: each method's mean (the median for time to 90 %), and
// the reference method against each other one: relative difference and
// Mann–Whitney p over the runs.
std::string ComparisonMarkdown(const std::vector<RunRecord>& records, const std::vector<std::string>& worlds,
                               const std::vector<std::string>& methods, double duration_s);

// Writes every report and figure of the finished runs in `options.out_dir`;
// returns the files written. Plotting failures throw std::runtime_error
// naming bench.log.
std::vector<std::string> WriteBenchReports(const BenchOptions& options);

}  // namespace aslam
