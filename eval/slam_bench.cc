#include "eval/slam_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/channels.h"
#include "common/lcm_log_writer.h"
#include "common/map_io.h"
#include "common/types_lcm.h"
#include "common/world_file.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/sim_config.h"
#include "drivers/sim/simulator.h"
#include "eval/stats.h"
#include "slam/occupancy_mapper.h"
#include "slam/slam.h"
#include "slam/slam_config.h"

namespace aslam {
namespace {

using Clock = std::chrono::steady_clock;

// Truth or odometry farther than this from a keyframe's time is not compared with it.
constexpr int64_t kMaxPoseGap_us = 100000;

// The odometry at the first keyframe that has one.
std::optional<Pose2d> OdometryAnchor(const std::vector<TimedPose>& keyframes,
                                     const std::vector<TimedPose>& odometry) {
  for (const TimedPose& k : keyframes) {
    if (const std::optional<Pose2d> o = PoseAt(odometry, k.utime, kMaxPoseGap_us)) return o;
  }
  return std::nullopt;
}

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// What one drive recorded besides Slam's own state.
struct DriveRecord {
  std::vector<TimedPose> truth;     // world
  std::vector<TimedPose> odometry;  // odom
  // Wall time of each AddScan call, ms: all, by kind, and with the map render it triggered.
  std::vector<double> all_ms, keyframe_ms, other_ms, closure_ms, render_ms, with_render_ms;
  std::vector<LidarScan> keyframe_scans;  // to time a full map re-render at the end
  int64_t odometry_dropped = 0;
  double slam_wall_s = 0.0;  // in AddOdometry and AddScan
};

// Feeds one scan to Slam, timing it and the map render SlamNode would do after it.
void AddTimedScan(const LidarScan& scan, Slam* slam, int64_t* rendered_revision,
                  int64_t* last_render_utime, DriveRecord* record) {
  const Clock::time_point t0 = Clock::now();
  const ScanUpdate update = slam->AddScan(scan);
  const double elapsed_s = SecondsSince(t0);
  record->slam_wall_s += elapsed_s;
  record->all_ms.push_back(elapsed_s * 1e3);
  (update.keyframe_added ? record->keyframe_ms : record->other_ms).push_back(elapsed_s * 1e3);
  if (update.keyframe_added) record->keyframe_scans.push_back(scan);
  if (update.loop_closures_accepted + update.loop_closures_rejected > 0) {
    record->closure_ms.push_back(elapsed_s * 1e3);
  }
  // The map as SlamNode renders it: at most 1 Hz by scan time, and after each closure.
  double render_s = 0.0;
  if (slam->map_revision() != *rendered_revision &&
      (update.map_invalidated || scan.utime - *last_render_utime >= 1000000)) {
    const Clock::time_point r0 = Clock::now();
    slam->RenderMap();
    render_s = SecondsSince(r0);
    record->render_ms.push_back(render_s * 1e3);
    *rendered_revision = slam->map_revision();
    *last_render_utime = scan.utime;
  }
  record->with_render_ms.push_back((elapsed_s + render_s) * 1e3);
}

void PrintProgress(const Simulator& simulator, const Slam* slam) {
  const Pose2d& p = simulator.true_pose();
  std::printf("t=%6.1f s  truth (%6.2f, %6.2f, %5.2f)", simulator.utime() * 1e-6, p.x_m, p.y_m,
              p.yaw_rad);
  if (slam) {
    std::printf("  keyframes %zu  closures %lld", slam->graph().nodes.size(),
                static_cast<long long>(slam->counters().loop_closures_accepted));
  }
  std::printf("\n");
  std::fflush(stdout);
}

// Steps the simulator along `drive` until `end_us`, recording its output and
// feeding it to `slam` (either may be null).
DriveRecord Drive(const ScriptedDrive& drive, int64_t end_us, double progress_period_s,
                  Simulator* simulator, Slam* slam, LcmLogWriter* recorder) {
  DriveRecord record;
  int64_t rendered_revision = -1;
  int64_t last_render_utime = -1000000000;
  const int64_t progress_us = std::llround(progress_period_s * 1e6);
  while (simulator->utime() < end_us) {
    const std::optional<VelocityCommand> command = drive.CommandAt(simulator->utime());
    if (!command) break;
    simulator->SetCommand(*command);
    const SimStepOutput out = simulator->Step();
    if (out.odometry) {
      record.odometry.push_back({out.odometry->utime, out.odometry->pose});
      if (recorder) {
        recorder->Write(channels::kOdometry, out.odometry->utime, ToLcm(*out.odometry));
      }
      if (slam) {
        const Clock::time_point t0 = Clock::now();
        if (!slam->AddOdometry(*out.odometry)) ++record.odometry_dropped;
        record.slam_wall_s += SecondsSince(t0);
      }
    }
    if (out.scan) {
      if (recorder) recorder->Write(channels::kLidarScan, out.scan->utime, ToLcm(*out.scan));
      if (slam) AddTimedScan(*out.scan, slam, &rendered_revision, &last_render_utime, &record);
    }
    if (out.truth) {
      record.truth.push_back({out.truth->utime, out.truth->pose});
      if (recorder) {
        recorder->Write(channels::kSimTruth, out.truth->utime, ToLcm(*out.truth, "world"));
      }
    }
    if (progress_us > 0 && simulator->utime() % progress_us == 0) PrintProgress(*simulator, slam);
  }
  return record;
}

void PrintTimes(const char* label, const std::vector<double>& times_ms) {
  double sum = 0.0;
  for (double t : times_ms) sum += t;
  std::printf("  %-16s n %6zu  mean %7.3f  median %7.3f  p90 %7.3f  p99 %7.3f  max %8.3f ms\n",
              label, times_ms.size(), times_ms.empty() ? 0.0 : sum / times_ms.size(),
              NearestRankPercentile(times_ms, 0.5), NearestRankPercentile(times_ms, 0.9),
              NearestRankPercentile(times_ms, 0.99),
              times_ms.empty() ? 0.0 : *std::max_element(times_ms.begin(), times_ms.end()));
}

void PrintTimings(const DriveRecord& record, const Slam& slam, const SlamOptions& slam_options) {
  std::printf("AddScan wall time:\n");
  PrintTimes("all scans", record.all_ms);
  PrintTimes("keyframe scans", record.keyframe_ms);
  PrintTimes("other scans", record.other_ms);
  PrintTimes("closure attempts", record.closure_ms);
  std::printf("map renders as SlamNode publishes them (<= 1 Hz and after each closure):\n");
  PrintTimes("renders", record.render_ms);
  PrintTimes("scan + render", record.with_render_ms);
  // What every closure pays besides matching and optimizing: all keyframes re-inserted.
  const PoseGraph& graph = slam.graph();
  OccupancyMapper mapper(slam_options.mapper);
  const Clock::time_point t0 = Clock::now();
  for (std::size_t i = 0; i < record.keyframe_scans.size() && i < graph.nodes.size(); ++i) {
    mapper.InsertScan(graph.nodes[i].pose, record.keyframe_scans[i]);
  }
  std::printf("  re-inserting all %zu keyframe scans into a map: %.3f ms\n",
              record.keyframe_scans.size(),
              std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
}

void PrintCounters(const Slam& slam, int64_t odometry_dropped) {
  const SlamCounters& c = slam.counters();
  std::printf(
      "loop closures: accepted %lld, rejected %lld (of which removed after optimization "
      "%lld); optimizations %lld; sequential matches below response %lld; keyframes explained "
      "by the map (graph only) %lld\n",
      static_cast<long long>(c.loop_closures_accepted),
      static_cast<long long>(c.loop_closures_rejected),
      static_cast<long long>(c.loop_closures_removed), static_cast<long long>(c.optimizations),
      static_cast<long long>(c.matches_low_response),
      static_cast<long long>(c.keyframes_not_mapped));
  std::printf("dropped inputs: %lld (odometry rejected %lld)",
              static_cast<long long>(c.dropped_total()), static_cast<long long>(odometry_dropped));
  for (int r = 0; r < static_cast<int>(DropReason::kCount); ++r) {
    if (c.dropped[r] > 0) {
      std::printf("  %s %lld", DropReasonName(static_cast<DropReason>(r)),
                  static_cast<long long>(c.dropped[r]));
    }
  }
  std::printf("\n");
}

// ATE of the keyframes, with odometry alone at the same times for comparison.
void PrintTrajectoryAccuracy(const std::vector<TimedPose>& keyframes, const DriveRecord& record) {
  const AteResult ate = ComputeAte(keyframes, record.truth);
  const AteResult odometry_ate =
      ComputeAte(OdometryAtKeyframes(keyframes, record.odometry), record.truth);
  std::printf(
      "keyframe ATE: RMSE %.4f m, mean %.4f m, max %.4f m (at t=%.1f s), yaw RMSE %.4f rad, "
      "yaw max %.4f rad; %d matched, %d unmatched\n",
      ate.rmse_m, ate.mean_m, ate.max_m, ate.max_utime * 1e-6, ate.yaw_rmse_rad, ate.yaw_max_rad,
      ate.matched, ate.unmatched);
  std::printf("odometry alone: RMSE %.4f m, max %.4f m, yaw max %.4f rad\n", odometry_ate.rmse_m,
              odometry_ate.max_m, odometry_ate.yaw_max_rad);
}

void PrintMapAgreement(const OccupancyGrid& map, const Pose2d& map_in_world,
                       const OccupancyGrid& world_map) {
  const MapAgreementOptions agreement_options;
  const MapAgreement agreement =
      ComputeMapAgreement(map, map_in_world, world_map, agreement_options);
  std::printf(
      "map %dx%d cells: occupied precision %.4f (%lld of %lld within %.2f m of a wall), "
      "free precision %.4f (%lld of %lld truly free), coverage %.4f of %.1f m2 free\n",
      map.width_cells(), map.height_cells(), agreement.occupied_precision,
      static_cast<long long>(agreement.occupied_near_wall),
      static_cast<long long>(agreement.slam_occupied_cells), agreement_options.wall_tolerance_m,
      agreement.free_precision, static_cast<long long>(agreement.free_truly_free),
      static_cast<long long>(agreement.slam_free_cells), agreement.coverage,
      agreement.truth_free_cells * world_map.resolution_m() * world_map.resolution_m());
}

void WriteOutputs(const std::string& out_dir, const OccupancyGrid& map,
                  const std::vector<TimedPose>& keyframes, const DriveRecord& record) {
  std::filesystem::create_directories(out_dir);
  if (!map.empty()) SaveMap(map, out_dir + "/map");
  std::ostringstream csv;
  WriteTrajectoryCsv(keyframes, record.truth, record.odometry, csv);
  WriteFileAtomically(out_dir + "/trajectory.csv", csv.str());
  std::printf("wrote %s/map.yaml, map.pgm, trajectory.csv\n", out_dir.c_str());
}

// The bench itself; throws on a failure.
void Run(const SlamBenchOptions& options) {
  SimulatorOptions sim_options = LoadSimulatorOptionsFromFile(options.config_path);
  if (options.seed >= 0) sim_options.seed = static_cast<uint64_t>(options.seed);
  const SlamOptions slam_options = LoadSlamOptionsFromFile(options.config_path);
  const WorldInfo world = LoadWorld(options.world_dir);
  if (!world.has_start) {
    throw std::runtime_error(options.world_dir + " has no start pose (world.yaml)");
  }
  const ScriptedDrive drive = LoadScriptedDrive(options.drive_path);
  const int64_t end_us = options.duration_s > 0 ? std::llround(options.duration_s * 1e6)
                                                : std::llround(drive.duration_s() * 1e6);

  Simulator simulator(world.map.grid, world.start, sim_options);
  std::optional<Slam> slam;
  if (options.run_slam) slam.emplace(slam_options);
  std::unique_ptr<LcmLogWriter> recorder;
  if (!options.record_log_path.empty()) {
    recorder = std::make_unique<LcmLogWriter>(options.record_log_path);
  }

  std::printf("aslam-slam-bench: %s, drive %s (%.1f s), seed %llu, running %.1f s\n",
              options.world_dir.c_str(), options.drive_path.c_str(), drive.duration_s(),
              static_cast<unsigned long long>(sim_options.seed), end_us * 1e-6);
  std::fflush(stdout);
  const Clock::time_point run_start = Clock::now();
  const DriveRecord record = Drive(drive, end_us, options.progress_period_s, &simulator,
                                   slam ? &*slam : nullptr, recorder.get());
  const double wall_s = SecondsSince(run_start);
  const double sim_s = simulator.utime() * 1e-6;

  std::printf("\nsimulated %.1f s in %.2f s wall: %.0f sim s per wall s; collisions %lld\n", sim_s,
              wall_s, sim_s / wall_s, static_cast<long long>(simulator.collisions()));
  if (slam) {
    std::printf("SLAM alone (AddOdometry + AddScan) %.2f s wall: %.0f sim s per wall s\n",
                record.slam_wall_s, sim_s / std::max(record.slam_wall_s, 1e-9));
  }
  if (recorder) {
    std::printf("recorded %lld events to %s (%lld bytes)\n",
                static_cast<long long>(recorder->events()), options.record_log_path.c_str(),
                static_cast<long long>(std::filesystem::file_size(options.record_log_path)));
  }
  if (!slam) return;

  const SlamCounters& c = slam->counters();
  const PoseGraph& graph = slam->graph();
  std::printf("scans %lld received, %lld processed; keyframes %zu; edges %zu; odometry %lld\n",
              static_cast<long long>(c.scans_received), static_cast<long long>(c.scans_processed),
              graph.nodes.size(), graph.edges.size(), static_cast<long long>(c.odometry_received));
  PrintTimings(record, *slam, slam_options);
  PrintCounters(*slam, record.odometry_dropped);
  const std::vector<TimedPose> keyframes = KeyframePoses(graph);
  PrintTrajectoryAccuracy(keyframes, record);

  const OccupancyGrid map = slam->RenderMap();
  const Pose2d map_in_world =
      keyframes.empty()
          ? world.start
          : PoseAt(record.truth, keyframes.front().utime, kMaxPoseGap_us).value_or(world.start);
  PrintMapAgreement(map, map_in_world, world.map.grid);
  if (!options.out_dir.empty()) WriteOutputs(options.out_dir, map, keyframes, record);
}

}  // namespace

int RunSlamBench(const SlamBenchOptions& options) {
  if (options.world_dir.empty() || options.drive_path.empty()) {
    std::fprintf(stderr, "aslam-slam-bench: --world and --drive are required\n");
    return 2;
  }
  if (options.duration_s < 0) {
    std::fprintf(stderr, "aslam-slam-bench: --duration must be >= 0\n");
    return 2;
  }
  try {
    Run(options);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-slam-bench: %s\n", e.what());
    return 1;
  }
}

std::vector<TimedPose> OdometryAtKeyframes(const std::vector<TimedPose>& keyframes,
                                           const std::vector<TimedPose>& odometry) {
  const std::optional<Pose2d> anchor = OdometryAnchor(keyframes, odometry);
  std::vector<TimedPose> relative;
  for (const TimedPose& k : keyframes) {
    const std::optional<Pose2d> o = PoseAt(odometry, k.utime, kMaxPoseGap_us);
    if (o) relative.push_back({k.utime, anchor->Between(*o)});
  }
  return relative;
}

void WriteTrajectoryCsv(const std::vector<TimedPose>& keyframes,
                        const std::vector<TimedPose>& truth, const std::vector<TimedPose>& odometry,
                        std::ostream& csv) {
  csv << "node,utime,x_m,y_m,yaw_rad,truth_x_m,truth_y_m,truth_yaw_rad,error_m,"
         "odometry_x_m,odometry_y_m,odometry_yaw_rad\n";
  const std::optional<Pose2d> truth_anchor =
      keyframes.empty() ? std::nullopt : PoseAt(truth, keyframes.front().utime, kMaxPoseGap_us);
  const std::optional<Pose2d> odometry_anchor = OdometryAnchor(keyframes, odometry);
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const TimedPose& k = keyframes[i];
    const std::optional<Pose2d> t = PoseAt(truth, k.utime, kMaxPoseGap_us);
    const std::optional<Pose2d> o = PoseAt(odometry, k.utime, kMaxPoseGap_us);
    csv << i << ',' << k.utime << ',' << k.pose.x_m << ',' << k.pose.y_m << ',' << k.pose.yaw_rad;
    if (t && truth_anchor) {
      const Pose2d tm = truth_anchor->Between(*t);
      csv << ',' << tm.x_m << ',' << tm.y_m << ',' << tm.yaw_rad << ','
          << std::hypot(k.pose.x_m - tm.x_m, k.pose.y_m - tm.y_m);
    } else {
      csv << ",,,,";
    }
    if (o && odometry_anchor) {
      const Pose2d om = odometry_anchor->Between(*o);
      csv << ',' << om.x_m << ',' << om.y_m << ',' << om.yaw_rad;
    } else {
      csv << ",,,";
    }
    csv << '\n';
  }
}

}  // namespace aslam
