#include "eval/bench.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "common/map_io.h"
#include "common/text_format.h"
#include "eval/map_metrics.h"
#include "slam/g2o_io.h"
#include "utility/utility_config.h"
#include "common/world_file.h"

extern char** environ;

namespace aslam {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

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

std::string ThisSourceDir() { return ASLAM_SOURCE_DIR; }

// 'text' for /bin/sh, whatever it holds (world names come from user folders).
std::string ShellQuote(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

double RunRecord::Number(const std::string& key) const {
  for (const auto& [k, v] : fields) {
    if (k != key) continue;
    if (v == "null" || v.empty()) return std::nan("");
    if (v == "true") return 1.0;
    if (v == "false") return 0.0;
    char* end = nullptr;
    const double value = std::strtod(v.c_str(), &end);
    return end && *end == '\0' ? value : std::nan("");
  }
  return std::nan("");
}

std::string ReferenceMethod(const std::vector<std::string>& methods) {
  if (methods.empty()) return "";
  return std::find(methods.begin(), methods.end(), "ours") != methods.end() ? "ours" : methods.back();
}

std::string ResolveWorld(const std::string& world) {
  if (fs::exists(world)) return world;
  const std::string shipped = ThisSourceDir() + "/worlds/" + world;
  if (world.find('/') == std::string::npos && fs::is_directory(shipped)) return shipped;
  return world;
}

std::string WorldLabel(const std::string& world) {
  fs::path path(world);
  while (path.has_parent_path() && path.filename().empty()) path = path.parent_path();  // trailing '/'
  if (fs::is_directory(path)) return path.filename().string();
  const std::string stem = path.stem().string();
  // DIR/world.yaml and DIR/map.yaml name the world by its folder.
  if ((stem == "world" || stem == "map") && path.has_parent_path()) return path.parent_path().filename().string();
  return stem;
}

std::vector<BenchRun> PlanBench(const BenchOptions& options) {
  if (options.worlds.empty()) throw std::invalid_argument("--worlds: no world given");
  if (options.methods.empty()) throw std::invalid_argument("--methods: no method given");
  for (const std::string& method : options.methods) {
    if (!ParseUtilityMethod(method)) throw std::invalid_argument("--methods: '" + method + "': expected fd, ags or ours");
  }
  if (options.seeds < 1) throw std::invalid_argument("--seeds must be >= 1");
  if (!(options.duration_s > 0)) throw std::invalid_argument("--duration must be > 0");
  if (options.jobs < 1) throw std::invalid_argument("--jobs must be >= 1");
  if (options.out_dir.empty()) throw std::invalid_argument("--out is required");
  std::set<std::string> labels;
  std::vector<std::pair<std::string, std::string>> worlds;  // (path, label)
  for (const std::string& given : options.worlds) {
    const std::string world = ResolveWorld(given);
    if (!fs::exists(world)) throw std::invalid_argument("--worlds: '" + given + "': no such world folder or map file");
    const std::string label = WorldLabel(world);
    if (!labels.insert(label).second) throw std::invalid_argument("--worlds: two worlds are named '" + label + "'");
    worlds.emplace_back(world, label);
  }
  std::vector<BenchRun> runs;
  for (int seed = 1; seed <= options.seeds; ++seed) {
    for (const auto& [world, label] : worlds) {
      for (const std::string& method : options.methods) {
        char seed_dir[32];
        std::snprintf(seed_dir, sizeof seed_dir, "seed_%02d", seed);
        runs.push_back({world, label, method, seed,
                        options.out_dir + "/runs/" + label + "/" + method + "/" + seed_dir});
      }
    }
  }
  return runs;
}

std::optional<RunRecord> ReadFinishedRun(const BenchRun& run) {
  const std::string path = run.dir + "/metrics.json";
  if (!fs::exists(path)) return std::nullopt;
  // JSON is YAML's flow style: yaml-cpp reads metrics.json without a JSON library.
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception&) {
    return std::nullopt;  // torn by a crash: rerun it
  }
  if (!root.IsMap()) return std::nullopt;
  RunRecord record{run, {}};
  for (const auto& entry : root) {
    record.fields.emplace_back(entry.first.as<std::string>(),
                               entry.second.IsNull() ? "null" : entry.second.as<std::string>());
  }
  for (const auto& [key, value] : record.fields) {
    if (key == "end_reason" && value == "interrupted") return std::nullopt;
  }
  return record;
}

BenchSummary RunBench(const BenchOptions& options, const std::atomic<bool>* stop,
                      const std::function<void(const BenchProgress&)>& on_progress) {
  const std::vector<BenchRun> runs = PlanBench(options);
  if (options.aslam_binary.empty()) throw std::invalid_argument("RunBench: no aslam binary");
  const Clock::time_point start = Clock::now();
  BenchSummary summary;
  summary.total = static_cast<int>(runs.size());

  std::vector<const BenchRun*> pending;
  for (const BenchRun& run : runs) {
    if (ReadFinishedRun(run)) {
      ++summary.skipped;
    } else {
      pending.push_back(&run);
    }
  }

  std::map<pid_t, std::pair<const BenchRun*, Clock::time_point>> running;
  std::vector<double> run_wall_s;
  std::size_t next = 0;
  auto report = [&] {
    if (!on_progress) return;
    BenchProgress p;
    p.total = summary.total;
    p.skipped = summary.skipped;
    p.finished = summary.finished;
    p.failed = static_cast<int>(summary.failed.size());
    p.running = static_cast<int>(running.size());
    p.elapsed_s = Since(start);
    if (!run_wall_s.empty()) {
      double mean = 0.0;
      for (const double w : run_wall_s) mean += w;
      mean /= run_wall_s.size();
      // Runs still to start, plus what the running ones have left, spread over the jobs.
      double left = (pending.size() - next) * mean;
      for (const auto& [pid, entry] : running) left += std::max(0.0, mean - Since(entry.second));
      p.eta_s = left / options.jobs;
    }
    on_progress(p);
  };

  auto spawn = [&](const BenchRun& run) {
    fs::create_directories(run.dir);
    std::vector<std::string> args = {options.aslam_binary, "explore", "--inproc", "--world", run.world,
                                     "--method", run.method, "--seed", std::to_string(run.seed),
                                     "--duration", Format("%.17g", options.duration_s), "--out", run.dir,
                                     "--progress", "60"};
    if (!options.config_file.empty()) args.insert(args.end(), {"--config", options.config_file});
    if (options.start) {
      args.insert(args.end(), {"--start", Format("%.17g", options.start->x_m) + "," +
                                              Format("%.17g", options.start->y_m) + "," +
                                              Format("%.17g", options.start->yaw_rad)});
    }
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    const std::string log = run.dir + "/explore.log";
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = 0;
    const int error = posix_spawn(&pid, options.aslam_binary.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (error != 0) throw std::runtime_error("cannot start " + options.aslam_binary + ": " + std::strerror(error));
    running[pid] = {&run, Clock::now()};
  };

  report();
  bool stopping = false;
  while (next < pending.size() || !running.empty()) {
    if (stop && stop->load() && !stopping) {
      stopping = true;
      summary.interrupted = true;
      // Children write an "interrupted" run folder, which a resumed bench reruns.
      for (const auto& [pid, entry] : running) kill(pid, SIGINT);
    }
    while (!stopping && next < pending.size() && static_cast<int>(running.size()) < options.jobs) {
      spawn(*pending[next++]);
      report();
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid <= 0) {
      if (stopping && running.empty()) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      continue;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const BenchRun& run = *it->second.first;
    const double wall_s = Since(it->second.second);
    running.erase(it);
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && ReadFinishedRun(run).has_value();
    if (ok) {
      ++summary.finished;
      run_wall_s.push_back(wall_s);
    } else if (!stopping) {
      summary.failed.push_back(run.dir);
    }
    report();
    if (stopping && running.empty()) break;
  }
  summary.wall_seconds = Since(start);
  return summary;
}

MeanStd ComputeMeanStd(const std::vector<double>& values) {
  MeanStd out;
  double sum = 0.0;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    sum += v;
    ++out.n;
  }
  if (out.n == 0) return {std::nan(""), std::nan(""), 0};
  out.mean = sum / out.n;
  double squares = 0.0;
  for (const double v : values) {
    if (std::isfinite(v)) squares += (v - out.mean) * (v - out.mean);
  }
  out.std = out.n > 1 ? std::sqrt(squares / (out.n - 1)) : 0.0;
  return out;
}

std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>> ComputeCurves(
    const std::vector<RunRecord>& records, double duration_s) {
  const int seconds = static_cast<int>(std::floor(duration_s + 1e-9));
  std::map<std::pair<std::string, std::string>, std::vector<std::vector<double>>> coverage, d_opt;
  for (const RunRecord& r : records) {
    const auto key = std::make_pair(r.run.world_label, r.run.method);
    coverage[key].push_back(PerSecond(ReadTimeline(r.run.dir + "/coverage.csv"), seconds));
    d_opt[key].push_back(PerSecond(ReadTimeline(r.run.dir + "/uncertainty.csv"), seconds));
  }
  std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>> curves;
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
  std::string out = "world_label,run_dir";
  for (const std::string& k : keys) out += "," + k;
  out += "\n";
  auto quoted = [](const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string q = "\"";
    for (const char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  for (const RunRecord& r : records) {
    out += quoted(r.run.world_label) + "," + quoted(r.run.dir);
    for (const std::string& k : keys) {
      std::string value;
      for (const auto& [fk, fv] : r.fields) {
        if (fk == k) value = fv == "null" ? "" : fv;
      }
      out += "," + quoted(value);
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
std::vector<double> ValuesOf(const std::vector<RunRecord>& records, const std::string& world, const std::string& method,
                             const std::string& key) {
  std::vector<double> values;
  for (const RunRecord& r : records) {
    if (r.run.world_label == world && r.run.method == method) values.push_back(r.Number(key));
  }
  return values;
}

}  // namespace

std::string Table1Markdown(const std::vector<RunRecord>& records, const std::vector<std::string>& worlds,
                           const std::vector<std::string>& methods) {
  std::string out = "| world | method | runs |";
  for (const RunMetric& c : kTable1Metrics) out += std::string(" ") + c.title + " |";
  out += "\n|---|---|---|";
  for (std::size_t i = 0; i < std::size(kTable1Metrics); ++i) out += "---|";
  out += "\n";
  for (const std::string& world : worlds) {
    for (const std::string& method : methods) {
      const std::size_t runs = ValuesOf(records, world, method, "coverage").size();  // one value per run
      out += "| " + world + " | " + method + " | " + std::to_string(runs) + " |";
      for (const RunMetric& c : kTable1Metrics) {
        out += " " + MeanStdCell(ComputeMeanStd(ValuesOf(records, world, method, c.key)), c.format) + " |";
      }
      out += "\n";
    }
  }
  return out;
}

std::string Table2Markdown(const std::vector<RunRecord>& records,
                           const std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>>& curves,
                           const std::vector<std::string>& worlds, const std::vector<std::string>& methods) {
  std::string out =
      "| world | method | runs | D-opt max & min (mean curve) | diff | %R (mean curve) | %R per run |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const std::string& world : worlds) {
    for (const std::string& method : methods) {
      const std::vector<double> per_run = ValuesOf(records, world, method, "d_opt_reduction_percent");
      std::vector<double> mean_curve;
      const auto it = curves.find({world, method});
      if (it != curves.end()) {
        for (const CurvePoint& p : it->second) mean_curve.push_back(p.d_opt.n > 0 ? p.d_opt.mean : std::nan(""));
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

std::string CurvesCsv(const std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>>& curves) {
  std::string out = "world,method,t_s,runs,coverage_mean,coverage_std,d_opt_mean,d_opt_std\n";
  auto number = [](double v) { return std::isfinite(v) ? Format("%.6g", v) : std::string(); };
  for (const auto& [key, curve] : curves) {
    for (const CurvePoint& p : curve) {
      out += key.first + "," + key.second + "," + Format("%.0f", p.t_s) + "," + std::to_string(p.coverage.n) + "," +
             number(p.coverage.mean) + "," + number(p.coverage.std) + "," + number(p.d_opt.mean) + "," +
             number(p.d_opt.std) + "\n";
    }
  }
  return out;
}

namespace {

// Time to 90 % coverage per run; +inf for a run that never got there, so it ranks after every run that did.
std::vector<double> TimesTo90(const std::vector<RunRecord>& records, const std::string& world,
                              const std::string& method) {
  std::vector<double> times_s = ValuesOf(records, world, method, "time_to_90_coverage_s");
  for (double& t : times_s) t = std::isfinite(t) ? t : INFINITY;
  return times_s;
}

// Median of the non-NaN values (+inf allowed); NaN if none.
double Median(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return std::isnan(v); }), values.end());
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2.0;
}

std::string TimeCell(double t_s, double duration_s) {
  if (std::isnan(t_s)) return "–";
  return std::isfinite(t_s) ? Format("%.0f s", t_s) : "> " + Format("%.0f s", duration_s);
}

}  // namespace

std::string CoverageMarkdown(const std::vector<RunRecord>& records,
                             const std::map<std::pair<std::string, std::string>, std::vector<CurvePoint>>& curves,
                             const std::vector<std::string>& worlds, const std::vector<std::string>& methods,
                             double duration_s) {
  const std::vector<double> checkpoints_s = {duration_s / 6.0, duration_s / 3.0, duration_s * 2.0 / 3.0, duration_s};
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
      const long reached = std::count_if(times_s.begin(), times_s.end(), [](double t) { return std::isfinite(t); });
      const std::string count = " (" + std::to_string(reached) + "/" + std::to_string(times_s.size()) + " reached)";
      out += " " + TimeCell(Median(times_s), duration_s) + (times_s.empty() ? "" : count) + " |\n";
    }
  }
  return out;
}

double MannWhitneyP(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<std::pair<double, bool>> pooled;  // (value, from a)
  for (const double v : a) {
    if (!std::isnan(v)) pooled.push_back({v, true});
  }
  for (const double v : b) {
    if (!std::isnan(v)) pooled.push_back({v, false});
  }
  std::sort(pooled.begin(), pooled.end());
  double n1 = 0.0, rank_sum_a = 0.0, tie_term = 0.0;
  for (std::size_t i = 0; i < pooled.size();) {
    std::size_t j = i;
    while (j + 1 < pooled.size() && pooled[j + 1].first == pooled[i].first) ++j;
    const double rank = (i + j) / 2.0 + 1.0;  // mid-rank of the tie group
    for (std::size_t k = i; k <= j; ++k) {
      if (pooled[k].second) {
        rank_sum_a += rank;
        n1 += 1.0;
      }
    }
    const double t = static_cast<double>(j - i + 1);
    tie_term += t * t * t - t;
    i = j + 1;
  }
  const double n = static_cast<double>(pooled.size());
  const double n2 = n - n1;
  if (n1 == 0.0 || n2 == 0.0) return std::nan("");
  const double u = rank_sum_a - n1 * (n1 + 1.0) / 2.0;
  const double variance = n1 * n2 / 12.0 * ((n + 1.0) - tie_term / (n * (n - 1.0)));
  if (variance <= 0.0) return 1.0;  // every value tied
  const double z = std::max(0.0, std::abs(u - n1 * n2 / 2.0) - 0.5) / std::sqrt(variance);
  return std::min(1.0, std::erfc(z / std::sqrt(2.0)));
}

std::string ComparisonMarkdown(const std::vector<RunRecord>& records, const std::vector<std::string>& worlds,
                               const std::vector<std::string>& methods, double duration_s) {
  const std::string reference = ReferenceMethod(methods);
  std::vector<std::string> others;
  for (const std::string& m : methods) {
    if (m != reference) others.push_back(m);
  }
  std::vector<RunMetric> metrics(std::begin(kTable1Metrics), std::end(kTable1Metrics));
  metrics.push_back({"time to 90 % coverage (median)", nullptr, ""});  // key nullptr: medians of TimesTo90
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
        values[m] = metric.key ? ValuesOf(records, world, m, metric.key) : TimesTo90(records, world, m);
        centre[m] = metric.key ? ComputeMeanStd(values[m]).mean : Median(values[m]);
      }
      out += "| " + world + " | " + metric.title + " |";
      for (const std::string& m : methods) {
        out += " " + (metric.key ? (std::isnan(centre[m]) ? "–" : Format(metric.format, centre[m]))
                                 : TimeCell(centre[m], duration_s)) +
               " |";
      }
      for (const std::string& m : others) {
        const double ref = centre[reference], other = centre[m];
        const double p = MannWhitneyP(values[reference], values[m]);
        const bool relative = std::isfinite(ref) && std::isfinite(other) && other != 0.0;
        out += " " + (relative ? Format("%+.1f %%", 100.0 * (ref - other) / std::abs(other)) : std::string("–")) +
               (std::isnan(p) ? "" : " (p = " + Format("%.2g", p) + ")") + " |";
      }
      out += "\n";
    }
  }
  return out;
}

namespace {

// Fig. 5's inputs for one world: the truth map, the SLAM map of one run on the
// truth's grid (both as grey PNGs), its pose graph in world coordinates and
// the extent, for matplotlib to draw one over the other.
void WriteFig5Inputs(const RunRecord& record, const std::string& out_prefix) {
  const WorldInfo world = LoadWorld(record.run.world);
  const OccupancyGrid& truth = world.map.grid;
  const LoadedMap slam = LoadMap(record.run.dir + "/map.yaml");
  const Pose2d map_in_world{record.Number("map_in_world_x_m"), record.Number("map_in_world_y_m"),
                            record.Number("map_in_world_yaw_rad")};
  cv::Mat truth_grey, slam_grey;  // MapToGrey's row 0 is the map's top row, as imshow wants
  MapToGrey(truth).convertTo(truth_grey, CV_8U, 255.0);
  MapToGrey(ResampleOnGrid(slam.grid, map_in_world, truth)).convertTo(slam_grey, CV_8U, 255.0);
  if (!cv::imwrite(out_prefix + "_truth.png", truth_grey) || !cv::imwrite(out_prefix + "_map.png", slam_grey)) {
    throw std::runtime_error("cannot write " + out_prefix + "_{truth,map}.png");
  }
  const PoseGraph graph = ReadG2o(record.run.dir + "/graph.g2o");
  std::string edges = "x0_m,y0_m,x1_m,y1_m,loop_closure\n";
  for (const PoseGraphEdge& e : graph.edges) {
    const Pose2d a = map_in_world * graph.nodes.at(e.from_id).pose;
    const Pose2d b = map_in_world * graph.nodes.at(e.to_id).pose;
    edges += Format("%.4f", a.x_m) + "," + Format("%.4f", a.y_m) + "," + Format("%.4f", b.x_m) + "," +
             Format("%.4f", b.y_m) + "," + (e.kind == EdgeKind::kLoopClosure ? "1" : "0") + "\n";
  }
  WriteText(out_prefix + "_graph.csv", edges);
  const double res = truth.resolution_m();
  WriteText(out_prefix + "_extent.csv",
            "x_min_m,x_max_m,y_min_m,y_max_m,method,seed,coverage,run_dir\n" + Format("%.4f", truth.origin_m().x_m) + "," +
                Format("%.4f", truth.origin_m().x_m + truth.width_cells() * res) + "," +
                Format("%.4f", truth.origin_m().y_m) + "," +
                Format("%.4f", truth.origin_m().y_m + truth.height_cells() * res) + "," + record.run.method + "," +
                std::to_string(record.run.seed) + "," + Format("%.4f", record.Number("coverage")) + "," +
                record.run.dir + "\n");
}

}  // namespace

std::vector<std::string> WriteBenchReports(const BenchOptions& options) {
  const std::vector<BenchRun> runs = PlanBench(options);
  std::vector<RunRecord> records;
  std::vector<std::string> worlds;
  for (const BenchRun& run : runs) {
    if (std::find(worlds.begin(), worlds.end(), run.world_label) == worlds.end()) worlds.push_back(run.world_label);
    if (auto record = ReadFinishedRun(run)) records.push_back(std::move(*record));
  }
  const std::string& out = options.out_dir;
  std::vector<std::string> written;
  auto write = [&](const std::string& name, const std::string& text) {
    WriteText(out + "/" + name, text);
    written.push_back(name);
  };
  const auto curves = ComputeCurves(records, options.duration_s);
  write("runs.csv", RunsCsv(records));
  write("table1.md", Table1Markdown(records, worlds, options.methods));
  write("table2.md", Table2Markdown(records, curves, worlds, options.methods));
  write("coverage.md", CoverageMarkdown(records, curves, worlds, options.methods, options.duration_s));
  write("comparison.md", ComparisonMarkdown(records, worlds, options.methods, options.duration_s));
  write("curves.csv", CurvesCsv(curves));

  // Fig. 5 shows the reference method's run of median coverage.
  const std::string fig5_method = ReferenceMethod(options.methods);
  std::vector<std::string> fig5_worlds;
  for (const std::string& world : worlds) {
    std::vector<const RunRecord*> group;
    for (const RunRecord& r : records) {
      if (r.run.world_label == world && r.run.method == fig5_method) group.push_back(&r);
    }
    if (group.empty()) continue;
    std::sort(group.begin(), group.end(), [](const RunRecord* a, const RunRecord* b) {
      return a->Number("coverage") < b->Number("coverage") ||
             (a->Number("coverage") == b->Number("coverage") && a->run.seed < b->run.seed);
    });
    WriteFig5Inputs(*group[group.size() / 2], out + "/fig5_" + world);
    fig5_worlds.push_back(world);
  }

  if (!options.plots) return written;
  std::string methods;
  for (const std::string& m : options.methods) methods += (methods.empty() ? "" : ",") + m;
  std::string world_list, all_worlds;
  for (const std::string& w : fig5_worlds) world_list += (world_list.empty() ? "" : ",") + w;
  for (const std::string& w : worlds) all_worlds += (all_worlds.empty() ? "" : ",") + w;
  // Debian's interpreter, which has python3-matplotlib (a pyenv python3 on PATH may not).
  const std::string command = "/usr/bin/python3 " + ShellQuote(ThisSourceDir() + "/eval/bench_plots.py") +
                              " --out " + ShellQuote(out) + " --methods " + ShellQuote(methods) + " --worlds " +
                              ShellQuote(all_worlds) + " --fig5-worlds " + ShellQuote(world_list) + " > " +
                              ShellQuote(out + "/bench.log") + " 2>&1";
  if (std::system(command.c_str()) != 0) {
    throw std::runtime_error("plotting failed (python3 eval/bench_plots.py): see " + out + "/bench.log");
  }
  written.push_back("fig3.png");
  written.push_back("fig4.png");
  for (const std::string& w : fig5_worlds) written.push_back("fig5_" + w + ".png");
  return written;
}

}  // namespace aslam
