#pragma once

// `aslam bench`'s report tables from the finished runs (docs/architecture.md §6):
// runs.csv, Table I (table1.md), Table II (table2.md), coverage.md,
// comparison.md, cost.md, ideal.md, goals.md, the mean curves (curves.csv) and a --set sweep's
// summary (sweep.md). Text only; the statistics come from eval/stats.h. The tables take one
// setting's runs; eval/bench.cc puts one section per setting in each file.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "eval/bench_runs.h"
#include "eval/stats.h"

namespace aslam {

// The method the others are compared with: "ours" when it ran, else the last.
std::string ReferenceMethod(const std::vector<std::string>& methods);

// Per (world, method) and per simulated second: mean ± std of coverage and of
// mean edge D-optimality over the runs. A run that ended early (done) holds
// its last value to the end.
struct CurvePoint {
  double t_s = 0.0;
  MeanStd coverage;
  MeanStd d_opt;
};
using BenchCurves = std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>>;
BenchCurves ComputeCurves(const std::vector<RunRecord>& records, double duration_s);

// The reports' text. With a sweep (any run with a setting), runs.csv starts with a
// `setting` column.
std::string RunsCsv(const std::vector<RunRecord>& records);
std::string Table1Markdown(const std::vector<RunRecord>& records,
                           const std::vector<std::string>& worlds,
                           const std::vector<std::string>& methods);
std::string Table2Markdown(const std::vector<RunRecord>& records, const BenchCurves& curves,
                           const std::vector<std::string>& worlds,
                           const std::vector<std::string>& methods);
std::string CurvesCsv(const BenchCurves& curves);
// curves.csv of a sweep: a first column `setting`, each setting's curves in the order given.
std::string CurvesCsv(const std::vector<std::pair<std::string, BenchCurves>>& curves_by_setting);
// Coverage % (mean ± std) at 1/6, 1/3, 2/3 and all of the duration (5, 10, 20
// and 30 min of the paper's 30), and the median time to 90 % coverage over all
// runs, a run that never reached 90 % counting as later than every run that did.
std::string CoverageMarkdown(const std::vector<RunRecord>& records, const BenchCurves& curves,
                             const std::vector<std::string>& worlds,
                             const std::vector<std::string>& methods, double duration_s);
// Per world and metric: each method's mean (the median for time to 90 %), and
// the reference method against each other one: relative difference and
// Mann–Whitney p over the runs.
std::string ComparisonMarkdown(const std::vector<RunRecord>& records,
                               const std::vector<std::string>& worlds,
                               const std::vector<std::string>& methods, double duration_s);
// What the runs cost (in-process runs' metrics.json): per world and method, the
// medians of simulated seconds per CPU second over the run and over its first and
// last 300 s, their ratio (1 = cost flat as the map grows), the median share of
// each node's CPU, and the CPU seconds of all runs together.
std::string CostMarkdown(const std::vector<RunRecord>& records,
                         const std::vector<std::string>& worlds,
                         const std::vector<std::string>& methods);
// The ideal explorer as the reference (issue 15): per world and method, over the seeds both ran,
// the method's time to 90 % and final coverage as ratios to the ideal's of the same seed
// (medians, and the worst seed). Says so when no ideal run is there.
std::string IdealMarkdown(const std::vector<RunRecord>& records,
                          const std::vector<std::string>& worlds,
                          const std::vector<std::string>& methods);
// Every goal accounted for: per world and method, decisions, goals by outcome (goals.csv's),
// failed and unreachable goals as a share of decisions, runs that were stuck, collisions; then
// the failures by reason, per method.
std::string GoalsMarkdown(const std::vector<RunRecord>& records,
                          const std::vector<std::string>& worlds,
                          const std::vector<std::string>& methods);
// A sweep in one table: per world, method and setting (settings adjacent, so a parameter's
// effect reads down the column), the runs and the medians of coverage, time to 90 % (never
// reached counting as the latest), ATE RMSE and algebraic connectivity.
std::string SweepMarkdown(const std::vector<RunRecord>& records,
                          const std::vector<std::string>& settings,
                          const std::vector<std::string>& worlds,
                          const std::vector<std::string>& methods, double duration_s);

}  // namespace aslam
