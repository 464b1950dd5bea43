#include "eval/bench.h"

#include <algorithm>
#include <filesystem>

#include "common/atomic_file.h"

namespace aslam {
namespace {

// One setting's finished runs and their mean curves.
struct SettingRecords {
  std::string label;  // "" without --set
  std::vector<RunRecord> records;
  BenchCurves curves;
};

}  // namespace

std::vector<std::string> WriteBenchReports(const BenchOptions& options) {
  const std::vector<BenchRun> runs = PlanBench(options);
  std::vector<SettingRecords> groups;
  std::vector<std::string> worlds;
  for (const BenchRun& run : runs) {
    if (std::find(worlds.begin(), worlds.end(), run.world_label) == worlds.end()) {
      worlds.push_back(run.world_label);
    }
    auto group = std::find_if(groups.begin(), groups.end(),
                              [&](const SettingRecords& g) { return g.label == run.setting; });
    if (group == groups.end()) group = groups.insert(groups.end(), {run.setting, {}, {}});
    if (auto record = ReadFinishedRun(run)) group->records.push_back(std::move(*record));
  }
  std::vector<RunRecord> records;  // every setting's, in plan order
  std::vector<std::string> labels;
  std::vector<std::pair<std::string, BenchCurves>> curves_by_setting;
  for (SettingRecords& group : groups) {
    group.curves = ComputeCurves(group.records, options.duration_s);
    records.insert(records.end(), group.records.begin(), group.records.end());
    labels.push_back(group.label);
    curves_by_setting.emplace_back(group.label, group.curves);
  }
  const bool sweep = !options.sweep.empty();
  const std::string& out = options.out_dir;
  std::vector<std::string> written;
  auto write = [&](const std::string& name, const std::string& text) {
    WriteFileAtomically(out + "/" + name, text);
    written.push_back(name);
  };
  // A table per setting, each under a heading naming it; without --set the one table alone.
  auto sections = [&](const auto& table) {
    if (!sweep) return table(groups.front());
    std::string text;
    for (const SettingRecords& group : groups) {
      text += (text.empty() ? "" : "\n") + std::string("## ") + group.label + "\n\n" + table(group);
    }
    return text;
  };
  const double duration_s = options.duration_s;
  const std::vector<std::string>& methods = options.methods;
  write("runs.csv", RunsCsv(records));
  write("table1.md", sections([&](const SettingRecords& g) {
          return Table1Markdown(g.records, worlds, methods);
        }));
  write("table2.md", sections([&](const SettingRecords& g) {
          return Table2Markdown(g.records, g.curves, worlds, methods);
        }));
  write("coverage.md", sections([&](const SettingRecords& g) {
          return CoverageMarkdown(g.records, g.curves, worlds, methods, duration_s);
        }));
  write("comparison.md", sections([&](const SettingRecords& g) {
          return ComparisonMarkdown(g.records, worlds, methods, duration_s);
        }));
  write("cost.md", sections([&](const SettingRecords& g) {
          return CostMarkdown(g.records, worlds, methods);
        }));
  write("ideal.md", sections([&](const SettingRecords& g) {
          return IdealMarkdown(g.records, worlds, methods);
        }));
  write("goals.md", sections([&](const SettingRecords& g) {
          return GoalsMarkdown(g.records, worlds, methods);
        }));
  write("curves.csv", sweep ? CurvesCsv(curves_by_setting) : CurvesCsv(groups.front().curves));
  if (sweep) write("sweep.md", SweepMarkdown(records, labels, worlds, methods, duration_s));

  // The figures of each setting: in OUT, or OUT/settings/<label>/ with --set.
  for (const SettingRecords& group : groups) {
    const std::string folder = sweep ? "settings/" + group.label + "/" : "";
    std::filesystem::create_directories(out + "/" + folder);
    // Fig. 5 shows the reference method's run of median coverage.
    const std::string fig5_method = ReferenceMethod(methods);
    std::vector<std::string> fig5_worlds;
    for (const std::string& world : worlds) {
      const RunRecord* shown = Fig5Run(group.records, world, fig5_method);
      if (!shown) continue;
      WriteFig5Inputs(*shown, out + "/" + folder + "fig5_" + world);
      fig5_worlds.push_back(world);
    }
    if (!options.plots) continue;
    for (const std::string& figure : DrawBenchPlots(out + "/" + folder, out + "/curves.csv",
                                                    group.label, methods, worlds, fig5_worlds)) {
      written.push_back(folder + figure);
    }
  }
  return written;
}

}  // namespace aslam
