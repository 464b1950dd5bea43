#include "eval/bench_report.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>

#include <yaml-cpp/yaml.h>

#include "common/text_format.h"
#include "eval/goal_ledger.h"

namespace aslam {
namespace {

// One column of a run's CSV timeline (t_s,value), indexed by whole second.
std::vector<std::pair<double, double>> ReadTimeline(const std::string& path) {
  std::vector<std::pair<double, double>> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    const auto comma = line.find(',');
    if (comma == std::string::npos) continue;
    const std::string value = line.substr(comma + 1);
    rows.emplace_back(std::strtod(line.c_str(), nullptr),
                      value.empty() ? std::nan("") : std::strtod(value.c_str(), nullptr));
  }
  return rows;
}

// Samples at t = 1, 2, ... duration s; after the run's last sample its last value holds.
std::vector<double> PerSecond(const std::vector<std::pair<double, double>>& rows, int seconds) {
  std::vector<double> out(seconds, std::nan(""));
  std::size_t i = 0;
  double last = std::nan("");
  for (int s = 1; s <= seconds; ++s) {
    while (i < rows.size() && rows[i].first <= s + 1e-6) last = rows[i++].second;
    out[s - 1] = last;
  }
  return out;
}

std::string MeanStdCell(const MeanStd& m, const char* format) {
  if (m.n == 0) return "–";
  return Format(format, m.mean) + " ± " + Format(format, m.std);
}

}  // namespace

std::string ReferenceMethod(const std::vector<std::string>& methods) {
  if (methods.empty()) return "";
  return std::find(methods.begin(), methods.end(), "ours") != methods.end() ? "ours"
                                                                            : methods.back();
}

BenchCurves ComputeCurves(const std::vector<RunRecord>& records, double duration_s) {
  const int seconds = static_cast<int>(std::floor(duration_s + 1e-9));
  std::map<std::pair<std::string, std::string>, std::vector<std::vector<double>>> coverage, d_opt;
  for (const RunRecord& r : records) {
    const auto key = std::make_pair(r.run.world_label, r.run.method);
    coverage[key].push_back(PerSecond(ReadTimeline(r.run.dir + "/coverage.csv"), seconds));
    d_opt[key].push_back(PerSecond(ReadTimeline(r.run.dir + "/uncertainty.csv"), seconds));
  }
  BenchCurves curves;
  for (const auto& [key, runs] : coverage) {
    std::vector<CurvePoint>& curve = curves[key];
    for (int s = 0; s < seconds; ++s) {
      std::vector<double> c, d;
      for (const auto& run : runs) c.push_back(run[s]);
      for (const auto& run : d_opt[key]) d.push_back(run[s]);
      curve.push_back({s + 1.0, ComputeMeanStd(c), ComputeMeanStd(d)});
    }
  }
  return curves;
}

std::string RunsCsv(const std::vector<RunRecord>& records) {
  // Columns: the union of every run's keys, in first-seen order.
  std::vector<std::string> keys;
  for (const RunRecord& r : records) {
    for (const auto& [k, v] : r.fields) {
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
    }
  }
  const bool sweep = std::any_of(records.begin(), records.end(),
                                 [](const RunRecord& r) { return !r.run.setting.empty(); });
  std::string out = sweep ? "setting,world_label,run_dir" : "world_label,run_dir";
  for (const std::string& k : keys) out += "," + k;
  out += "\n";
  for (const RunRecord& r : records) {
    if (sweep) out += CsvField(r.run.setting) + ",";
    out += CsvField(r.run.world_label) + "," + CsvField(r.run.dir);
    for (const std::string& k : keys) {
      std::string value;
      for (const auto& [fk, fv] : r.fields) {
        if (fk == k) value = fv == "null" ? "" : fv;
      }
      out += "," + CsvField(value);
    }
    out += "\n";
  }
  return out;
}

namespace {

// A per-run metric of metrics.json as a table column.
struct RunMetric {
  const char* title;
  const char* key;
  const char* format;
};
// Table I's columns: the paper's, then final coverage and ATE.
constexpr RunMetric kTable1Metrics[] = {
    {"A.C", "algebraic_connectivity", "%.3f"},
    {"avg degree", "average_degree", "%.3f"},
    {"norm. tree conn.", "normalized_tree_connectivity", "%.3f"},
    {"SSIM", "ssim", "%.3f"},
    {"RMSE", "map_rmse", "%.3f"},
    {"coverage", "coverage", "%.3f"},
    {"ATE RMSE (m)", "ate_rmse_m", "%.3f"},
};

// The metric's value in each run of (world, method), NaN where missing.
std::vector<double> ValuesOf(const std::vector<RunRecord>& records, const std::string& world,
                             const std::string& method, const std::string& key) {
  std::vector<double> values;
  for (const RunRecord& r : records) {
    if (r.run.world_label == world && r.run.method == method) values.push_back(r.Number(key));
  }
  return values;
}

}  // namespace

std::string Table1Markdown(const std::vector<RunRecord>& records,
                           const std::vector<std::string>& worlds,
                           const std::vector<std::string>& methods) {
  std::string out = "| world | method | runs |";
  for (const RunMetric& c : kTable1Metrics) out += std::string(" ") + c.title + " |";
  out += "\n|---|---|---|";
  for (std::size_t i = 0; i < std::size(kTable1Metrics); ++i) out += "---|";
  out += "\n";
  for (const std::string& world : worlds) {
    for (const std::string& method : methods) {
      const std::size_t runs =
          ValuesOf(records, world, method, "coverage").size();  // one value per run
      out += "| " + world + " | " + method + " | " + std::to_string(runs) + " |";
      for (const RunMetric& c : kTable1Metrics) {
        out += " " +
               MeanStdCell(ComputeMeanStd(ValuesOf(records, world, method, c.key)), c.format) +
               " |";
      }
      out += "\n";
    }
  }
  return out;
}

std::string Table2Markdown(const std::vector<RunRecord>& records, const BenchCurves& curves,
                           const std::vector<std::string>& worlds,
                           const std::vector<std::string>& methods) {
  std::string out =
      "| world | method | runs | D-opt max & min (mean curve) | diff | %R (mean curve) | %R per "
      "run |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const std::string& world : worlds) {
    for (const std::string& method : methods) {
      const std::vector<double> per_run =
          ValuesOf(records, world, method, "d_opt_reduction_percent");
      std::vector<double> mean_curve;
      const auto it = curves.find({world, method});
      if (it != curves.end()) {
        for (const CurvePoint& p : it->second)
          mean_curve.push_back(p.d_opt.n > 0 ? p.d_opt.mean : std::nan(""));
      }
      double max = -INFINITY, min = INFINITY;
      for (const double v : mean_curve) {
        if (!std::isfinite(v)) continue;
        max = std::max(max, v);
        min = std::min(min, v);
      }
      const bool any = std::isfinite(max);
      out += "| " + world + " | " + method + " | " + std::to_string(per_run.size()) + " | " +
             (any ? Format("%.1f", max) + " & " + Format("%.1f", min) : "–") + " | " +
             (any ? Format("%.1f", max - min) : "–") + " | " +
             (any && max > 0 ? Format("%.1f", 100.0 * (max - min) / max) : "–") + " | " +
             MeanStdCell(ComputeMeanStd(per_run), "%.1f") + " |\n";
    }
  }
  return out;
}

namespace {

constexpr char kCurvesHeader[] =
    "world,method,t_s,runs,coverage_mean,coverage_std,d_opt_mean,d_opt_std\n";

// curves.csv's rows, each after `prefix` (a sweep's setting column).
std::string CurvesRows(const BenchCurves& curves, const std::string& prefix) {
  std::string out;
  auto number = [](double v) { return std::isfinite(v) ? Format("%.6g", v) : std::string(); };
  for (const auto& [key, curve] : curves) {
    for (const CurvePoint& p : curve) {
      out += prefix + key.first + "," + key.second + "," + Format("%.0f", p.t_s) + "," +
             std::to_string(p.coverage.n) + "," + number(p.coverage.mean) + "," +
             number(p.coverage.std) + "," + number(p.d_opt.mean) + "," + number(p.d_opt.std) + "\n";
    }
  }
  return out;
}

}  // namespace

std::string CurvesCsv(const BenchCurves& curves) { return kCurvesHeader + CurvesRows(curves, ""); }

std::string CurvesCsv(const std::vector<std::pair<std::string, BenchCurves>>& curves_by_setting) {
  std::string out = std::string("setting,") + kCurvesHeader;
  for (const auto& [setting, curves] : curves_by_setting)
    out += CurvesRows(curves, CsvField(setting) + ",");
  return out;
}

namespace {

// Time to 90 % coverage per run; +inf for a run that never got there, so it ranks after every run
// that did.
std::vector<double> TimesTo90(const std::vector<RunRecord>& records, const std::string& world,
                              const std::string& method) {
  std::vector<double> times_s = ValuesOf(records, world, method, "time_to_90_coverage_s");
  for (double& t : times_s) t = std::isfinite(t) ? t : INFINITY;
  return times_s;
}

std::string TimeCell(double t_s, double duration_s) {
  if (std::isnan(t_s)) return "–";
  return std::isfinite(t_s) ? Format("%.0f s", t_s) : "> " + Format("%.0f s", duration_s);
}

}  // namespace

std::string CoverageMarkdown(const std::vector<RunRecord>& records, const BenchCurves& curves,
                             const std::vector<std::string>& worlds,
                             const std::vector<std::string>& methods, double duration_s) {
  const std::vector<double> checkpoints_s = {duration_s / 6.0, duration_s / 3.0,
                                             duration_s * 2.0 / 3.0, duration_s};
  std::string out = "| world | method | runs |";
  for (const double t : checkpoints_s) out += " coverage % at " + Format("%.0f", t) + " s |";
  out += " median time to 90 % |\n|---|---|---|";
  for (std::size_t i = 0; i <= checkpoints_s.size(); ++i) out += "---|";
  out += "\n";
  for (const std::string& world : worlds) {
    for (const std::string& method : methods) {
      const std::vector<double> times_s = TimesTo90(records, world, method);
      out += "| " + world + " | " + method + " | " + std::to_string(times_s.size()) + " |";
      const auto it = curves.find({world, method});
      for (const double t : checkpoints_s) {
        const int i = static_cast<int>(std::lround(t)) - 1;  // curve[i] holds second i + 1
        if (it == curves.end() || i < 0 || i >= static_cast<int>(it->second.size())) {
          out += " – |";
          continue;
        }
        const MeanStd& c = it->second[i].coverage;
        out += " " + MeanStdCell({100.0 * c.mean, 100.0 * c.std, c.n}, "%.1f") + " |";
      }
      const long reached =
          std::count_if(times_s.begin(), times_s.end(), [](double t) { return std::isfinite(t); });
      const std::string count =
          " (" + std::to_string(reached) + "/" + std::to_string(times_s.size()) + " reached)";
      out += " " + TimeCell(Median(times_s), duration_s) + (times_s.empty() ? "" : count) + " |\n";
    }
  }
  return out;
}

std::string CostMarkdown(const std::vector<RunRecord>& records,
                         const std::vector<std::string>& worlds,
                         const std::vector<std::string>& methods) {
  static const char* const kNodes[] = {"sim", "slam", "frontier", "utility", "nav", "evaluation"};
  std::string out =
      "| world | method | runs | sim s per CPU s | first 300 s | last 300 s | last / first |";
  for (const char* node : kNodes) out += std::string(" ") + node + " % |";
  out += " CPU s, all runs |\n|---|---|---|---|---|---|---|";
  for (std::size_t i = 0; i <= std::size(kNodes); ++i) out += "---|";
  out += "\n";
  auto cell = [](double value, const char* format) {
    return std::isfinite(value) ? Format(format, value) : std::string("–");
  };
  for (const std::string& world : worlds) {
    for (const std::string& method : methods) {
      const std::vector<double> first = ValuesOf(records, world, method, "sim_per_cpu_first_300s");
      const std::vector<double> last = ValuesOf(records, world, method, "sim_per_cpu_last_300s");
      const std::vector<double> totals = ValuesOf(records, world, method, "node_cpu_s.total");
      std::vector<double> ratios;
      for (std::size_t i = 0; i < first.size(); ++i) ratios.push_back(last[i] / first[i]);
      double cpu_sum_s = 0.0;
      for (const double t : totals) cpu_sum_s += std::isnan(t) ? 0.0 : t;
      out += "| " + world + " | " + method + " | " + std::to_string(totals.size()) + " | " +
             cell(Median(ValuesOf(records, world, method, "sim_per_cpu")), "%.1f") + " | " +
             cell(Median(first), "%.1f") + " | " + cell(Median(last), "%.1f") + " | " +
             cell(Median(ratios), "%.2f") + " |";
      for (const char* node : kNodes) {
        const std::vector<double> node_s =
            ValuesOf(records, world, method, std::string("node_cpu_s.") + node);
        std::vector<double> shares;
        for (std::size_t i = 0; i < node_s.size(); ++i)
          shares.push_back(100 * node_s[i] / totals[i]);
        out += " " + cell(Median(shares), "%.0f") + " |";
      }
      out += " " + cell(cpu_sum_s, "%.0f") + " |\n";
    }
  }
  return out;
}

std::string ComparisonMarkdown(const std::vector<RunRecord>& records,
                               const std::vector<std::string>& worlds,
                               const std::vector<std::string>& methods, double duration_s) {
  const std::string reference = ReferenceMethod(methods);
  std::vector<std::string> others;
  for (const std::string& m : methods) {
    if (m != reference) others.push_back(m);
  }
  std::vector<RunMetric> metrics(std::begin(kTable1Metrics), std::end(kTable1Metrics));
  metrics.push_back(
      {"time to 90 % coverage (median)", nullptr, ""});  // key nullptr: medians of TimesTo90
  metrics.push_back({"%R per run", "d_opt_reduction_percent", "%.1f"});
  std::string out = "| world | metric |";
  for (const std::string& m : methods) out += " " + m + " |";
  for (const std::string& m : others) out += " " + reference + " vs " + m + " |";
  out += "\n|---|---|";
  for (std::size_t i = 0; i < methods.size() + others.size(); ++i) out += "---|";
  out += "\n";
  for (const std::string& world : worlds) {
    for (const RunMetric& metric : metrics) {
      std::map<std::string, std::vector<double>> values;
      std::map<std::string, double> centre;
      for (const std::string& m : methods) {
        values[m] =
            metric.key ? ValuesOf(records, world, m, metric.key) : TimesTo90(records, world, m);
        centre[m] = metric.key ? ComputeMeanStd(values[m]).mean : Median(values[m]);
      }
      out += "| " + world + " | " + metric.title + " |";
      for (const std::string& m : methods) {
        out += " " +
               (metric.key ? (std::isnan(centre[m]) ? "–" : Format(metric.format, centre[m]))
                           : TimeCell(centre[m], duration_s)) +
               " |";
      }
      for (const std::string& m : others) {
        const double ref = centre[reference], other = centre[m];
        const double p = MannWhitneyP(values[reference], values[m]);
        const bool relative = std::isfinite(ref) && std::isfinite(other) && other != 0.0;
        out += " " +
               (relative ? Format("%+.1f %%", 100.0 * (ref - other) / std::abs(other))
                         : std::string("–")) +
               (std::isnan(p) ? "" : " (p = " + Format("%.2g", p) + ")") + " |";
      }
      out += "\n";
    }
  }
  return out;
}

std::string SweepMarkdown(const std::vector<RunRecord>& records,
                          const std::vector<std::string>& settings,
                          const std::vector<std::string>& worlds,
                          const std::vector<std::string>& methods, double duration_s) {
  std::string out =
      "| world | method | setting | runs | coverage | time to 90 % | ATE RMSE (m) | A.C |\n"
      "|---|---|---|---|---|---|---|---|\n";
  auto median_cell = [](const std::vector<double>& values, const char* format) {
    const double median = Median(values);
    return std::isnan(median) ? std::string("–") : Format(format, median);
  };
  for (const std::string& world : worlds) {
    for (const std::string& method : methods) {
      for (const std::string& setting : settings) {
        std::vector<RunRecord> group;
        for (const RunRecord& r : records) {
          if (r.run.setting == setting) group.push_back(r);
        }
        const std::vector<double> times_s = TimesTo90(group, world, method);
        out += "| " + world + " | " + method + " | " + setting + " | " +
               std::to_string(times_s.size()) + " | " +
               median_cell(ValuesOf(group, world, method, "coverage"), "%.3f") + " | " +
               TimeCell(Median(times_s), duration_s) + " | " +
               median_cell(ValuesOf(group, world, method, "ate_rmse_m"), "%.3f") + " | " +
               median_cell(ValuesOf(group, world, method, "algebraic_connectivity"), "%.3f") +
               " |\n";
      }
    }
  }
  return out;
}

namespace {

// A run's value of `key` by seed, for one world and method.
std::map<int, double> BySeed(const std::vector<RunRecord>& records, const std::string& world,
                             const std::string& method, const std::string& key) {
  std::map<int, double> values;
  for (const RunRecord& r : records) {
    if (r.run.world_label == world && r.run.method == method) values[r.run.seed] = r.Number(key);
  }
  return values;
}

std::string RatioCell(std::vector<double> ratios) {
  if (ratios.empty()) return "–";
  const double worst = *std::max_element(ratios.begin(), ratios.end());
  auto text = [](double r) { return std::isfinite(r) ? Format("%.2f", r) : std::string("never"); };
  return text(Median(ratios)) + " (" + text(worst) + ")";
}

}  // namespace

std::string IdealMarkdown(const std::vector<RunRecord>& records,
                          const std::vector<std::string>& worlds,
                          const std::vector<std::string>& methods) {
  const bool any_ideal = std::any_of(records.begin(), records.end(),
                                     [](const RunRecord& r) { return r.run.method == "ideal"; });
  if (!any_ideal) return "No ideal runs: add ideal to --methods for the reference.\n";
  std::string out =
      "Each method against the ideal explorer (true pose, nearest frontier by path) of the same "
      "world and seed: median over the seeds, the worst seed in brackets. Time to 90 %: method / "
      "ideal (never: the method did not reach 90 % where the ideal did; a seed where the ideal "
      "did not is left out). Coverage: method's final / ideal's final (worst: the lowest).\n\n"
      "| world | method | seeds | time to 90 % / ideal's | final coverage / ideal's |\n"
      "|---|---|---|---|---|\n";
  for (const std::string& world : worlds) {
    const std::map<int, double> ideal_t = BySeed(records, world, "ideal", "time_to_90_coverage_s");
    const std::map<int, double> ideal_c = BySeed(records, world, "ideal", "coverage");
    for (const std::string& method : methods) {
      if (method == "ideal") continue;
      const std::map<int, double> t = BySeed(records, world, method, "time_to_90_coverage_s");
      const std::map<int, double> c = BySeed(records, world, method, "coverage");
      std::vector<double> time_ratios, coverage_ratios;
      int seeds = 0;
      for (const auto& [seed, coverage] : c) {
        const auto ideal = ideal_c.find(seed);
        if (ideal == ideal_c.end()) continue;
        ++seeds;
        if (ideal->second > 0) coverage_ratios.push_back(coverage / ideal->second);
        const double ideal_time = ideal_t.at(seed);
        if (!std::isfinite(ideal_time)) continue;
        const double time = t.at(seed);
        time_ratios.push_back(std::isfinite(time) ? time / ideal_time : INFINITY);
      }
      const std::string coverage_cell =
          coverage_ratios.empty()
              ? "–"
              : Format("%.3f (%.3f)", Median(coverage_ratios),
                       *std::min_element(coverage_ratios.begin(), coverage_ratios.end()));
      out += "| " + world + " | " + method + " | " + std::to_string(seeds) + " | " +
             RatioCell(time_ratios) + " | " + coverage_cell + " |\n";
    }
  }
  return out;
}

std::string GoalsMarkdown(const std::vector<RunRecord>& records,
                          const std::vector<std::string>& worlds,
                          const std::vector<std::string>& methods) {
  std::string out = "| world | method | runs | decisions |";
  for (const GoalOutcome outcome : kAllGoalOutcomes)
    out += std::string(" ") + GoalOutcomeName(outcome) + " |";
  out += " failed + unreachable, % of decisions | stuck runs | collisions |\n|---|---|---|---|";
  for (std::size_t i = 0; i < std::size(kAllGoalOutcomes) + 3; ++i) out += "---|";
  out += "\n";
  auto sum = [](const std::vector<double>& values) {
    double total = 0.0;
    for (const double v : values) total += std::isnan(v) ? 0.0 : v;
    return total;
  };
  std::string reasons;
  for (const std::string& world : worlds) {
    for (const std::string& method : methods) {
      const std::vector<double> decisions = ValuesOf(records, world, method, "decisions");
      if (decisions.empty()) continue;
      out += "| " + world + " | " + method + " | " + std::to_string(decisions.size()) + " | " +
             Format("%.0f", sum(decisions)) + " |";
      for (const GoalOutcome outcome : kAllGoalOutcomes) {
        const std::string key = std::string("goal_outcomes.") + GoalOutcomeName(outcome);
        out += " " + Format("%.0f", sum(ValuesOf(records, world, method, key))) + " |";
      }
      const double failed = sum(ValuesOf(records, world, method, "goal_outcomes.failed")) +
                            sum(ValuesOf(records, world, method, "goal_outcomes.unreachable"));
      const std::vector<double> stuck = ValuesOf(records, world, method, "stuck_episodes");
      const long stuck_runs =
          std::count_if(stuck.begin(), stuck.end(), [](double n) { return n > 0; });
      out += " " + (sum(decisions) > 0 ? Format("%.1f", 100.0 * failed / sum(decisions)) : "–") +
             " | " + std::to_string(stuck_runs) + " | " +
             Format("%.0f", sum(ValuesOf(records, world, method, "collisions"))) + " |\n";

      // The runs' failures by reason, summed (metrics.json's goal_failures_by_reason).
      std::map<std::string, int> by_reason;
      for (const RunRecord& r : records) {
        if (r.run.world_label != world || r.run.method != method) continue;
        for (const auto& [key, text] : r.fields) {
          if (key != "goal_failures_by_reason") continue;
          try {
            for (const YAML::Node& entry : YAML::Load(text))
              by_reason[entry["reason"].as<std::string>()] += entry["goals"].as<int>();
          } catch (const YAML::Exception&) {
            by_reason["(unreadable in " + r.run.dir + "/metrics.json)"] += 0;
          }
        }
      }
      std::vector<std::pair<std::string, int>> sorted(by_reason.begin(), by_reason.end());
      std::stable_sort(sorted.begin(), sorted.end(),
                       [](const auto& a, const auto& b) { return a.second > b.second; });
      for (const auto& [reason, goals] : sorted) {
        reasons +=
            "| " + world + " | " + method + " | " + reason + " | " + std::to_string(goals) + " |\n";
      }
    }
  }
  out +=
      "\nFailed and unreachable goals by reason (numbers in the navigator's words as N, points "
      "as (x; y)):\n\n| world | method | reason | goals |\n|---|---|---|---|\n";
  return out + (reasons.empty() ? "| – | – | none | 0 |\n" : reasons);
}

}  // namespace aslam
