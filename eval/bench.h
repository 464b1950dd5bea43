#pragma once

// `aslam bench`: the paper's experiment (Tables I and II, Figs. 3–5) as one
// command. Runs the world × method × seed matrix in-process, each run an
// `aslam bench-task` child (eval/bench_run_list.h) running `aslam explore
// --inproc` into its own run folder, J at a time (or as a Slurm array job:
// eval/bench_slurm.h); a run whose folder holds a finished metrics.json is
// skipped, so an interrupted bench resumes where it stopped (eval/bench_runs.h). Then
// aggregates every finished run into the reports (eval/bench_report.h, with
// eval/stats.h) and figures (eval/bench_plots.h: matplotlib, eval/bench_plots.py).
//
// Layout of OUT: runs/<world>/<method>/seed_<NN>/ (run folders, with the
// child's output in explore.log), runs.csv, table1.md, table2.md,
// coverage.md, comparison.md, cost.md, curves.csv, fig3.png, fig4.png,
// fig5_<world>.png (+ fig5_<world>_*.{png,csv} inputs of that figure),
// bench.log (the plotting tool's output).
// With --set (eval/bench_settings.h): runs/<label>/<world>/<method>/seed_<NN>/;
// settings/<label>/ holds the setting's config.yaml, figures and bench.log;
// each markdown report has one section per setting ("## <label>"), runs.csv and
// curves.csv a first column `setting`, and sweep.md sums the sweep up in one table.

#include <string>
#include <vector>

#include "eval/bench_plots.h"
#include "eval/bench_report.h"
#include "eval/bench_runs.h"
#include "eval/stats.h"

namespace aslam {

// Writes every report and figure of the finished runs in `options.out_dir`;
// returns the files written. Plotting failures throw std::runtime_error
// naming bench.log.
std::vector<std::string> WriteBenchReports(const BenchOptions& options);

}  // namespace aslam
