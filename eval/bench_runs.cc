#include "eval/bench_runs.h"

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <list>
#include <set>
#include <stdexcept>
#include <thread>

#include <yaml-cpp/yaml.h>

#include "common/subprocess.h"
#include "eval/bench_run_list.h"
#include "eval/explore_runner.h"
#include "utility/utility_config.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A run's `aslam explore --inproc` child.
struct RunningChild {
  const BenchRun* run = nullptr;
  Clock::time_point started;
  Subprocess process;
};

// A JSON object's scalars in file order; a nested object's as "outer.inner" (node_cpu_s.slam),
// an array as its flow text.
void AddFields(const YAML::Node& object, const std::string& prefix,
               std::vector<std::pair<std::string, std::string>>* fields) {
  for (const auto& entry : object) {
    const std::string key = prefix + entry.first.as<std::string>();
    const YAML::Node& value = entry.second;
    if (value.IsMap()) {
      AddFields(value, key + ".", fields);
    } else if (value.IsSequence()) {
      YAML::Emitter flow;
      flow << YAML::Flow << value;
      fields->emplace_back(key, flow.c_str());
    } else {
      fields->emplace_back(key, value.IsNull() ? "null" : value.as<std::string>());
    }
  }
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

std::string ResolveWorld(const std::string& world) {
  if (fs::exists(world)) return world;
  const std::string shipped = std::string(ASLAM_SOURCE_DIR) + "/worlds/" + world;
  if (world.find('/') == std::string::npos && fs::is_directory(shipped)) return shipped;
  return world;
}

std::string WorldLabel(const std::string& world) {
  fs::path path(world);
  while (path.has_parent_path() && path.filename().empty())
    path = path.parent_path();  // trailing '/'
  if (fs::is_directory(path)) return path.filename().string();
  const std::string stem = path.stem().string();
  // DIR/world.yaml and DIR/map.yaml name the world by its folder.
  if ((stem == "world" || stem == "map") && path.has_parent_path())
    return path.parent_path().filename().string();
  return stem;
}

std::string RunName(const BenchRun& run) {
  char seed_dir[32];
  std::snprintf(seed_dir, sizeof seed_dir, "seed_%02d", run.seed);
  return (run.setting.empty() ? "" : run.setting + "/") + run.world_label + "/" + run.method + "/" +
         seed_dir;
}

std::vector<BenchRun> PlanBench(const BenchOptions& options) {
  if (options.worlds.empty()) throw std::invalid_argument("--worlds: no world given");
  if (options.methods.empty()) throw std::invalid_argument("--methods: no method given");
  for (const std::string& method : options.methods) {
    ParseExploreMethod(method, "--methods:");
  }
  if (options.seeds < 1) throw std::invalid_argument("--seeds must be >= 1");
  CheckDuration(options.duration_s);
  if (options.jobs < 1) throw std::invalid_argument("--jobs must be >= 1");
  if (options.out_dir.empty()) throw std::invalid_argument("--out is required");
  std::set<std::string> labels;
  std::vector<std::pair<std::string, std::string>> worlds;  // (path, label)
  for (const std::string& given : options.worlds) {
    const std::string world = ResolveWorld(given);
    if (!fs::exists(world))
      throw std::invalid_argument("--worlds: '" + given + "': no such world folder or map file");
    const std::string label = WorldLabel(world);
    if (!labels.insert(label).second)
      throw std::invalid_argument("--worlds: two worlds are named '" + label + "'");
    worlds.emplace_back(world, label);
  }
  const std::vector<BenchSetting> settings = PlanSettings(options.sweep);
  std::vector<BenchRun> runs;
  for (int seed = 1; seed <= options.seeds; ++seed) {
    for (const BenchSetting& setting : settings) {
      const std::string config = setting.label.empty()
                                     ? options.config_file
                                     : SettingConfigPath(options.out_dir, setting.label);
      for (const auto& [world, label] : worlds) {
        for (const std::string& method : options.methods) {
          BenchRun run{world, label, method, seed, "", setting.label, config};
          run.dir = options.out_dir + "/runs/" + RunName(run);
          runs.push_back(std::move(run));
        }
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
  AddFields(root, "", &record.fields);
  for (const auto& [key, value] : record.fields) {
    if (key == "end_reason" && value == "interrupted") return std::nullopt;
  }
  return record;
}

BenchSummary RunBench(const BenchOptions& options, const std::atomic<bool>* stop,
                      const std::function<void(const BenchProgress&)>& on_progress) {
  const std::vector<BenchRun> runs = PlanBench(options);
  if (options.aslam_binary.empty()) throw std::invalid_argument("RunBench: no aslam binary");
  WriteSettingConfigs(options.config_file, PlanSettings(options.sweep), options.out_dir);
  const Clock::time_point start = Clock::now();
  BenchSummary summary;
  summary.total = static_cast<int>(runs.size());

  std::vector<const BenchRun*> pending;
  std::vector<RunListEntry> run_list;
  for (const BenchRun& run : runs) {
    if (ReadFinishedRun(run)) {
      ++summary.skipped;
    } else {
      pending.push_back(&run);
      run_list.push_back(MakeRunListEntry(options, run));
    }
  }
  const std::string run_list_path = options.out_dir + "/run_list.tsv";
  WriteRunList(run_list_path, run_list);

  std::list<RunningChild> running;
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
      for (const RunningChild& child : running) left += std::max(0.0, mean - Since(child.started));
      p.eta_s = left / options.jobs;
    }
    on_progress(p);
  };

  auto spawn = [&](std::size_t index) {
    const BenchRun& run = *pending[index];
    fs::create_directories(run.dir);
    SubprocessOptions spawn;
    spawn.argv = BenchTaskArgv(options.aslam_binary, run_list_path, static_cast<int>(index));
    spawn.output_path = run.dir + "/explore.log";
    spawn.append_output = true;  // a rerun keeps the failed attempt's output above its own
    try {
      Subprocess process = Subprocess::Spawn(spawn);
      running.push_back({&run, Clock::now(), std::move(process)});
    } catch (const SpawnError& e) {
      throw std::runtime_error("cannot start " + options.aslam_binary + ": " +
                               std::strerror(e.error_number()));
    }
  };

  report();
  bool stopping = false;
  while (next < pending.size() || !running.empty()) {
    if (stop && stop->load() && !stopping) {
      stopping = true;
      summary.interrupted = true;
      // Children write an "interrupted" run folder, which a resumed bench reruns.
      for (RunningChild& child : running) child.process.Signal(SIGINT);
    }
    while (!stopping && next < pending.size() && static_cast<int>(running.size()) < options.jobs) {
      spawn(next++);
      report();
    }
    bool any_ended = false;
    for (auto it = running.begin(); it != running.end();) {
      const std::optional<ExitStatus> status = it->process.Poll();
      if (!status) {
        ++it;
        continue;
      }
      const BenchRun& run = *it->run;
      const double wall_s = Since(it->started);
      it = running.erase(it);
      any_ended = true;
      const bool finished = ReadFinishedRun(run).has_value();
      if (status->success() && finished) {
        ++summary.finished;
        run_wall_s.push_back(wall_s);
      } else if (!stopping) {
        const std::string why =
            status->success() ? "ended without a finished metrics.json" : status->Describe();
        summary.failed.push_back({run, why, {run.dir + "/explore.log"}});
      }
      report();
    }
    if (stopping && running.empty()) break;
    if (!any_ended) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  summary.wall_seconds = Since(start);
  return summary;
}

}  // namespace aslam
