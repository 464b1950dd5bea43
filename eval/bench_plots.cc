#include "eval/bench_plots.h"

#include <algorithm>
#include <stdexcept>

#include <opencv2/core.hpp>

#include "common/atomic_file.h"
#include "common/map_io.h"
#include "common/subprocess.h"
#include "common/text_format.h"
#include "common/world_file.h"
#include "eval/map_metrics.h"
#include "slam/g2o_io.h"

namespace aslam {
namespace {

std::string Joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ",") + item;
  return text;
}

}  // namespace

const RunRecord* Fig5Run(const std::vector<RunRecord>& records, const std::string& world,
                         const std::string& method) {
  std::vector<const RunRecord*> group;
  for (const RunRecord& r : records) {
    if (r.run.world_label == world && r.run.method == method) group.push_back(&r);
  }
  if (group.empty()) return nullptr;
  std::sort(group.begin(), group.end(), [](const RunRecord* a, const RunRecord* b) {
    return a->Number("coverage") < b->Number("coverage") ||
           (a->Number("coverage") == b->Number("coverage") && a->run.seed < b->run.seed);
  });
  return group[group.size() / 2];
}

void WriteFig5Inputs(const RunRecord& record, const std::string& out_prefix) {
  const WorldInfo world = LoadWorld(record.run.world);
  const OccupancyGrid& truth = world.map.grid;
  const LoadedMap slam = LoadMap(record.run.dir + "/map.yaml");
  const Pose2d map_in_world{record.Number("map_in_world_x_m"), record.Number("map_in_world_y_m"),
                            record.Number("map_in_world_yaw_rad")};
  cv::Mat truth_grey, slam_grey;  // MapToGrey's row 0 is the map's top row, as imshow wants
  MapToGrey(truth).convertTo(truth_grey, CV_8U, 255.0);
  MapToGrey(ResampleOnGrid(slam.grid, map_in_world, truth)).convertTo(slam_grey, CV_8U, 255.0);
  WriteImageAtomically(out_prefix + "_truth.png", truth_grey);
  WriteImageAtomically(out_prefix + "_map.png", slam_grey);
  const PoseGraph graph = ReadG2o(record.run.dir + "/graph.g2o");
  std::string edges = "x0_m,y0_m,x1_m,y1_m,loop_closure\n";
  for (const PoseGraphEdge& e : graph.edges) {
    const Pose2d a = map_in_world * graph.nodes.at(e.from_id).pose;
    const Pose2d b = map_in_world * graph.nodes.at(e.to_id).pose;
    edges += Format("%.4f", a.x_m) + "," + Format("%.4f", a.y_m) + "," + Format("%.4f", b.x_m) +
             "," + Format("%.4f", b.y_m) + "," + (e.kind == EdgeKind::kLoopClosure ? "1" : "0") +
             "\n";
  }
  WriteFileAtomically(out_prefix + "_graph.csv", edges);
  const double res = truth.resolution_m();
  WriteFileAtomically(out_prefix + "_extent.csv",
                      "x_min_m,x_max_m,y_min_m,y_max_m,method,seed,coverage,run_dir\n" +
                          Format("%.4f", truth.origin_m().x_m) + "," +
                          Format("%.4f", truth.origin_m().x_m + truth.width_cells() * res) + "," +
                          Format("%.4f", truth.origin_m().y_m) + "," +
                          Format("%.4f", truth.origin_m().y_m + truth.height_cells() * res) + "," +
                          record.run.method + "," + std::to_string(record.run.seed) + "," +
                          Format("%.4f", record.Number("coverage")) + "," + record.run.dir + "\n");
}

std::vector<std::string> DrawBenchPlots(const std::string& out_dir, const std::string& curves_csv,
                                        const std::string& setting,
                                        const std::vector<std::string>& methods,
                                        const std::vector<std::string>& worlds,
                                        const std::vector<std::string>& fig5_worlds) {
  SubprocessOptions plot;
  // Debian's interpreter, which has python3-matplotlib (a pyenv python3 on PATH may not).
  plot.argv = {"/usr/bin/python3",
               std::string(ASLAM_SOURCE_DIR) + "/eval/bench_plots.py",
               "--out",
               out_dir,
               "--curves",
               curves_csv,
               "--setting",
               setting,
               "--methods",
               Joined(methods),
               "--worlds",
               Joined(worlds),
               "--fig5-worlds",
               Joined(fig5_worlds)};
  plot.output_path = out_dir + "/bench.log";
  const std::string failed =
      "plotting failed (python3 eval/bench_plots.py): see " + out_dir + "/bench.log";
  try {
    if (!Subprocess::Spawn(plot).Wait().success()) throw std::runtime_error(failed);
  } catch (const SpawnError& e) {
    WriteFileAtomically(plot.output_path, std::string(e.what()) + "\n");
    throw std::runtime_error(failed);
  }
  std::vector<std::string> figures = {"fig3.png", "fig4.png"};
  for (const std::string& w : fig5_worlds) figures.push_back("fig5_" + w + ".png");
  return figures;
}

}  // namespace aslam
