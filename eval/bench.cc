#include "eval/bench.h"

#include <algorithm>

namespace aslam {

std::vector<std::string> WriteBenchReports(const BenchOptions& options) {
  const std::vector<BenchRun> runs = PlanBench(options);
  std::vector<RunRecord> records;
  std::vector<std::string> worlds;
  for (const BenchRun& run : runs) {
    if (std::find(worlds.begin(), worlds.end(), run.world_label) == worlds.end()) {
      worlds.push_back(run.world_label);
    }
    if (auto record = ReadFinishedRun(run)) records.push_back(std::move(*record));
  }
  const std::string& out = options.out_dir;
  std::vector<std::string> written;
  auto write = [&](const std::string& name, const std::string& text) {
    WriteBenchFile(out + "/" + name, text);
    written.push_back(name);
  };
  const BenchCurves curves = ComputeCurves(records, options.duration_s);
  write("runs.csv", RunsCsv(records));
  write("table1.md", Table1Markdown(records, worlds, options.methods));
  write("table2.md", Table2Markdown(records, curves, worlds, options.methods));
  write("coverage.md",
        CoverageMarkdown(records, curves, worlds, options.methods, options.duration_s));
  write("comparison.md", ComparisonMarkdown(records, worlds, options.methods, options.duration_s));
  write("curves.csv", CurvesCsv(curves));

  // Fig. 5 shows the reference method's run of median coverage.
  const std::string fig5_method = ReferenceMethod(options.methods);
  std::vector<std::string> fig5_worlds;
  for (const std::string& world : worlds) {
    const RunRecord* shown = Fig5Run(records, world, fig5_method);
    if (!shown) continue;
    WriteFig5Inputs(*shown, out + "/fig5_" + world);
    fig5_worlds.push_back(world);
  }

  if (!options.plots) return written;
  for (const std::string& figure : DrawBenchPlots(out, options.methods, worlds, fig5_worlds)) {
    written.push_back(figure);
  }
  return written;
}

}  // namespace aslam
