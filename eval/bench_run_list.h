#pragma once

// A bench's run list: the runs one invocation executes, one per line, with everything a run needs
// (absolute paths, so a task on another machine of a shared filesystem finds them). It is the one
// hand-off between scheduling and running: `aslam bench --jobs` spawns, and each task of a Slurm
// array job (eval/bench_slurm.h) runs, `aslam bench-task LIST N`, which execs `aslam explore
// --inproc` for line N with its output appended to RUN/explore.log.
//
// The file: a '#' comment, a header line, then one tab-separated line per run:
//   dir  world  method  seed  duration_s  config  start
// `config` and `start` (X,Y,YAW) may be empty; no field may hold a tab or a newline.

#include <optional>
#include <string>
#include <vector>

#include "common/pose2d.h"
#include "eval/bench_runs.h"

namespace aslam {

struct RunListEntry {
  std::string dir;  // the run folder
  std::string world;
  std::string method;
  int seed = 0;
  double duration_s = 0.0;
  std::string config_file;  // "" = built-in defaults
  std::optional<Pose2d> start;
};

// `run` of a bench with `options`, its paths made absolute.
RunListEntry MakeRunListEntry(const BenchOptions& options, const BenchRun& run);

// Writes the list atomically. Throws std::invalid_argument naming the field that holds a tab or a
// newline, std::runtime_error when the file cannot be written.
void WriteRunList(const std::string& path, const std::vector<RunListEntry>& entries);

// Throws std::runtime_error naming the file (and line) when it cannot be read or a line is
// malformed: wrong field count, a seed or duration that is not a number, an unknown method.
std::vector<RunListEntry> ReadRunList(const std::string& path);

// `aslam_binary explore --inproc ...` for the entry.
std::vector<std::string> ExploreArgv(const std::string& aslam_binary, const RunListEntry& entry);

// `aslam_binary bench-task LIST INDEX`: what runs line `index` of a list.
std::vector<std::string> BenchTaskArgv(const std::string& aslam_binary, const std::string& list,
                                       int index);

// `aslam bench-task LIST INDEX`: creates the run folder, appends a header naming the run and this
// host to RUN/explore.log, sends stdout and stderr there and execs `aslam explore --inproc`
// (ExploreArgv). A run that has already finished is not run again: returns 0. Returns only
// without exec: 0 for a finished run, else 1 after printing why to stderr.
int ExecBenchTask(const std::string& aslam_binary, const std::string& list,
                  const std::string& index);

}  // namespace aslam
