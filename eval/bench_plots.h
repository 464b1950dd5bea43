#pragma once

// `aslam bench`'s figures: Fig. 5's inputs (truth and SLAM map images, pose
// graph and extent as CSV) and the call of python3 eval/bench_plots.py that
// draws fig3.png, fig4.png and fig5_<world>.png (matplotlib) from the bench
// folder's files: in OUT, or with --set one set per setting in OUT/settings/<label>/.

#include <string>
#include <vector>

#include "eval/bench_runs.h"

namespace aslam {

// The run Fig. 5 shows for `world`: `method`'s run of median coverage (ties by
// seed); nullptr if that method has no finished run there.
const RunRecord* Fig5Run(const std::vector<RunRecord>& records, const std::string& world,
                         const std::string& method);

// Fig. 5's inputs for one run: PREFIX_truth.png (the world's map) and
// PREFIX_map.png (the run's SLAM map on the truth's grid), both grey, PREFIX_graph.csv
// (its pose graph in world coordinates) and PREFIX_extent.csv, for matplotlib
// to draw one over the other. Throws std::runtime_error naming a file it cannot write.
void WriteFig5Inputs(const RunRecord& record, const std::string& out_prefix);

// Draws the figures into `out_dir` (the plotting tool's output in out_dir/bench.log)
// from `curves_csv`'s rows of `setting` ("": a bench without --set) and out_dir's
// Fig. 5 inputs, and returns their names. Throws std::runtime_error naming
// bench.log if plotting fails.
std::vector<std::string> DrawBenchPlots(const std::string& out_dir, const std::string& curves_csv,
                                        const std::string& setting,
                                        const std::vector<std::string>& methods,
                                        const std::vector<std::string>& worlds,
                                        const std::vector<std::string>& fig5_worlds);

}  // namespace aslam
