// aslam-slam-bench: runs the simulator in-process along a scripted drive and
// feeds its odometry and scans straight into Slam (no LCM), timing every
// AddScan call; then reports timing, keyframe ATE against the simulator's
// truth (and what odometry alone would give), loop closures and how well the
// map agrees with the world. Optionally records the simulator's output as an
// LCM log (the replay fixtures) and writes the map and the trajectory.
//
// The wall clock is read here for timing only; Slam sees message time.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gflags/gflags.h>
#include <lcm/lcm-cpp.hpp>

#include "common/channels.h"
#include "common/flags.h"
#include "common/map_io.h"
#include "common/types_lcm.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/sim_config.h"
#include "drivers/sim/simulator.h"
#include "slam/occupancy_mapper.h"
#include "slam/slam.h"
#include "slam/slam_config.h"
#include "eval/trajectory_metrics.h"
#include "common/world_file.h"

DEFINE_string(world, "", "world folder (map.yaml + world.yaml)");
DEFINE_string(drive, "", "scripted drive file (config/drives/*.yaml)");
DEFINE_string(config, "", "config file with `sim:` and `slam:` sections (default: built-in defaults)");
DEFINE_int64(seed, -1, "simulator seed; overrides the config's sim.seed when >= 0");
DEFINE_double(duration, 0.0, "simulated seconds to run; 0 = the whole drive");
DEFINE_string(out, "", "directory for map.yaml + map.pgm and trajectory.csv (created)");
DEFINE_string(record_log, "",
              "also write ODOMETRY, LIDAR_SCAN and SIM_TRUTH to this LCM log (event time = sim time)");
DEFINE_bool(slam, true, "run SLAM (--noslam with --record-log only records)");
DEFINE_double(progress, 60.0, "print a progress line every this many simulated seconds; 0 = never");

namespace aslam {
namespace {

using Clock = std::chrono::steady_clock;

double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  // Nearest rank: the smallest value with at least `fraction` of the values at or below it.
  const std::size_t rank = static_cast<std::size_t>(std::ceil(fraction * values.size()));
  return values[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
}

void PrintTimes(const char* label, const std::vector<double>& times_ms) {
  double sum = 0.0;
  for (double t : times_ms) sum += t;
  std::printf("  %-16s n %6zu  mean %7.3f  median %7.3f  p90 %7.3f  p99 %7.3f  max %8.3f ms\n",
              label, times_ms.size(), times_ms.empty() ? 0.0 : sum / times_ms.size(),
              Percentile(times_ms, 0.5), Percentile(times_ms, 0.9), Percentile(times_ms, 0.99),
              times_ms.empty() ? 0.0 : *std::max_element(times_ms.begin(), times_ms.end()));
}

// Writes encoded messages as log events stamped with their sim time.
class LogRecorder {
 public:
  explicit LogRecorder(const std::string& path) : log_(path, "w") {
    if (!log_.good()) throw std::runtime_error("cannot write LCM log " + path);
  }
  template <typename Msg>
  void Write(const char* channel, int64_t utime, const Msg& msg) {
    buffer_.resize(msg.getEncodedSize());
    msg.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
    lcm::LogEvent event{};
    event.timestamp = utime;
    event.channel = channel;
    event.datalen = static_cast<int32_t>(buffer_.size());
    event.data = buffer_.data();
    if (log_.writeEvent(&event) != 0) throw std::runtime_error("writing the LCM log failed");
    ++events_;
  }
  int64_t events() const { return events_; }

 private:
  lcm::LogFile log_;
  std::vector<uint8_t> buffer_;
  int64_t events_ = 0;
};

int Run() {
  if (FLAGS_world.empty() || FLAGS_drive.empty()) {
    std::fprintf(stderr, "aslam-slam-bench: --world and --drive are required\n");
    return 2;
  }
  if (FLAGS_duration < 0) {
    std::fprintf(stderr, "aslam-slam-bench: --duration must be >= 0\n");
    return 2;
  }
  try {
    SimulatorOptions sim_options = LoadSimulatorOptionsFromFile(FLAGS_config);
    if (FLAGS_seed >= 0) sim_options.seed = static_cast<uint64_t>(FLAGS_seed);
    const SlamOptions slam_options = LoadSlamOptionsFromFile(FLAGS_config);
    const WorldInfo world = LoadWorld(FLAGS_world);
    if (!world.has_start) throw std::runtime_error(FLAGS_world + " has no start pose (world.yaml)");
    const ScriptedDrive drive = LoadScriptedDrive(FLAGS_drive);
    const int64_t end_us = FLAGS_duration > 0 ? std::llround(FLAGS_duration * 1e6)
                                              : std::llround(drive.duration_s() * 1e6);

    Simulator simulator(world.map.grid, world.start, sim_options);
    std::optional<Slam> slam;
    if (FLAGS_slam) slam.emplace(slam_options);
    std::unique_ptr<LogRecorder> recorder;
    if (!FLAGS_record_log.empty()) recorder = std::make_unique<LogRecorder>(FLAGS_record_log);

    std::printf("aslam-slam-bench: %s, drive %s (%.1f s), seed %llu, running %.1f s\n",
                FLAGS_world.c_str(), FLAGS_drive.c_str(), drive.duration_s(),
                static_cast<unsigned long long>(sim_options.seed), end_us * 1e-6);
    std::fflush(stdout);

    std::vector<TimedPose> truth;     // world
    std::vector<TimedPose> odometry;  // odom
    std::vector<double> all_ms, keyframe_ms, other_ms, closure_ms, render_ms, with_render_ms;
    int64_t rendered_revision = -1;
    int64_t last_render_utime = -1000000000;
    std::vector<LidarScan> keyframe_scans;  // to time a full map re-render at the end
    int64_t odometry_dropped = 0;
    double slam_wall_s = 0.0;
    const int64_t progress_us = std::llround(FLAGS_progress * 1e6);
    const Clock::time_point run_start = Clock::now();

    while (simulator.utime() < end_us) {
      const std::optional<VelocityCommand> command = drive.CommandAt(simulator.utime());
      if (!command) break;
      simulator.SetCommand(*command);
      const SimStepOutput out = simulator.Step();
      if (out.odometry) {
        odometry.push_back({out.odometry->utime, out.odometry->pose});
        if (recorder) recorder->Write(channels::kOdometry, out.odometry->utime, ToLcm(*out.odometry));
        if (slam) {
          const Clock::time_point t0 = Clock::now();
          if (!slam->AddOdometry(*out.odometry)) ++odometry_dropped;
          slam_wall_s += std::chrono::duration<double>(Clock::now() - t0).count();
        }
      }
      if (out.scan) {
        if (recorder) recorder->Write(channels::kLidarScan, out.scan->utime, ToLcm(*out.scan));
        if (slam) {
          const Clock::time_point t0 = Clock::now();
          const ScanUpdate update = slam->AddScan(*out.scan);
          const double elapsed_s = std::chrono::duration<double>(Clock::now() - t0).count();
          slam_wall_s += elapsed_s;
          all_ms.push_back(elapsed_s * 1e3);
          (update.keyframe_added ? keyframe_ms : other_ms).push_back(elapsed_s * 1e3);
          if (update.keyframe_added) keyframe_scans.push_back(*out.scan);
          if (update.loop_closures_accepted + update.loop_closures_rejected > 0) {
            closure_ms.push_back(elapsed_s * 1e3);
          }
          // The map as SlamNode renders it: at most 1 Hz by scan time, and after each closure.
          double render_s = 0.0;
          if (slam->map_revision() != rendered_revision &&
              (update.map_invalidated || out.scan->utime - last_render_utime >= 1000000)) {
            const Clock::time_point r0 = Clock::now();
            slam->RenderMap();
            render_s = std::chrono::duration<double>(Clock::now() - r0).count();
            render_ms.push_back(render_s * 1e3);
            rendered_revision = slam->map_revision();
            last_render_utime = out.scan->utime;
          }
          with_render_ms.push_back((elapsed_s + render_s) * 1e3);
        }
      }
      if (out.truth) {
        truth.push_back({out.truth->utime, out.truth->pose});
        if (recorder) recorder->Write(channels::kSimTruth, out.truth->utime, ToLcm(*out.truth, "world"));
      }
      if (progress_us > 0 && simulator.utime() % progress_us == 0) {
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
    }
    const double wall_s = std::chrono::duration<double>(Clock::now() - run_start).count();
    const double sim_s = simulator.utime() * 1e-6;

    std::printf("\nsimulated %.1f s in %.2f s wall: %.0f sim s per wall s; collisions %lld\n", sim_s,
                wall_s, sim_s / wall_s, static_cast<long long>(simulator.collisions()));
    if (slam) {
      std::printf("SLAM alone (AddOdometry + AddScan) %.2f s wall: %.0f sim s per wall s\n",
                  slam_wall_s, sim_s / std::max(slam_wall_s, 1e-9));
    }
    if (recorder) {
      std::printf("recorded %lld events to %s (%lld bytes)\n", static_cast<long long>(recorder->events()),
                  FLAGS_record_log.c_str(),
                  static_cast<long long>(std::filesystem::file_size(FLAGS_record_log)));
    }
    if (!slam) return 0;

    const SlamCounters& c = slam->counters();
    const PoseGraph& graph = slam->graph();
    std::printf("scans %lld received, %lld processed; keyframes %zu; edges %zu; odometry %lld\n",
                static_cast<long long>(c.scans_received), static_cast<long long>(c.scans_processed),
                graph.nodes.size(), graph.edges.size(), static_cast<long long>(c.odometry_received));
    std::printf("AddScan wall time:\n");
    PrintTimes("all scans", all_ms);
    PrintTimes("keyframe scans", keyframe_ms);
    PrintTimes("other scans", other_ms);
    PrintTimes("closure attempts", closure_ms);
    std::printf("map renders as SlamNode publishes them (<= 1 Hz and after each closure):\n");
    PrintTimes("renders", render_ms);
    PrintTimes("scan + render", with_render_ms);
    {
      // What every closure pays besides matching and optimizing: all keyframes re-inserted.
      OccupancyMapper mapper(slam_options.mapper);
      const Clock::time_point t0 = Clock::now();
      for (std::size_t i = 0; i < keyframe_scans.size() && i < graph.nodes.size(); ++i) {
        mapper.InsertScan(graph.nodes[i].pose, keyframe_scans[i]);
      }
      std::printf("  re-inserting all %zu keyframe scans into a map: %.3f ms\n", keyframe_scans.size(),
                  std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
    std::printf("loop closures: accepted %lld, rejected %lld (of which removed after optimization "
                "%lld); optimizations %lld; sequential matches below response %lld\n",
                static_cast<long long>(c.loop_closures_accepted),
                static_cast<long long>(c.loop_closures_rejected),
                static_cast<long long>(c.loop_closures_removed),
                static_cast<long long>(c.optimizations),
                static_cast<long long>(c.matches_low_response));
    std::printf("dropped inputs: %lld (odometry rejected %lld)", static_cast<long long>(c.dropped_total()),
                static_cast<long long>(odometry_dropped));
    for (int r = 0; r < static_cast<int>(DropReason::kCount); ++r) {
      if (c.dropped[r] > 0) {
        std::printf("  %s %lld", DropReasonName(static_cast<DropReason>(r)),
                    static_cast<long long>(c.dropped[r]));
      }
    }
    std::printf("\n");

    // ATE of the keyframes; odometry alone at the same times for comparison.
    const std::vector<TimedPose> keyframes = KeyframePoses(graph);
    const AteResult ate = ComputeAte(keyframes, truth);
    std::vector<TimedPose> odometry_at_keyframes;
    std::optional<Pose2d> odometry_anchor;
    for (const TimedPose& k : keyframes) {
      const std::optional<Pose2d> o = PoseAt(odometry, k.utime, 100000);
      if (!o) continue;
      if (!odometry_anchor) odometry_anchor = *o;
      odometry_at_keyframes.push_back({k.utime, odometry_anchor->Between(*o)});
    }
    const AteResult odometry_ate = ComputeAte(odometry_at_keyframes, truth);
    std::printf("keyframe ATE: RMSE %.4f m, mean %.4f m, max %.4f m (at t=%.1f s), yaw RMSE %.4f rad, "
                "yaw max %.4f rad; %d matched, %d unmatched\n",
                ate.rmse_m, ate.mean_m, ate.max_m, ate.max_utime * 1e-6, ate.yaw_rmse_rad,
                ate.yaw_max_rad, ate.matched, ate.unmatched);
    std::printf("odometry alone: RMSE %.4f m, max %.4f m, yaw max %.4f rad\n", odometry_ate.rmse_m,
                odometry_ate.max_m, odometry_ate.yaw_max_rad);

    const OccupancyGrid map = slam->RenderMap();
    const Pose2d map_in_world =
        keyframes.empty() ? world.start
                          : PoseAt(truth, keyframes.front().utime, 100000).value_or(world.start);
    const MapAgreementOptions agreement_options;
    const MapAgreement agreement =
        ComputeMapAgreement(map, map_in_world, world.map.grid, agreement_options);
    std::printf("map %dx%d cells: occupied precision %.4f (%lld of %lld within %.2f m of a wall), "
                "free precision %.4f (%lld of %lld truly free), coverage %.4f of %.1f m2 free\n",
                map.width_cells(), map.height_cells(), agreement.occupied_precision,
                static_cast<long long>(agreement.occupied_near_wall),
                static_cast<long long>(agreement.slam_occupied_cells),
                agreement_options.wall_tolerance_m, agreement.free_precision,
                static_cast<long long>(agreement.free_truly_free),
                static_cast<long long>(agreement.slam_free_cells), agreement.coverage,
                agreement.truth_free_cells * world.map.grid.resolution_m() *
                    world.map.grid.resolution_m());

    if (!FLAGS_out.empty()) {
      std::filesystem::create_directories(FLAGS_out);
      if (!map.empty()) SaveMap(map, FLAGS_out + "/map");
      std::ofstream csv(FLAGS_out + "/trajectory.csv");
      csv << "node,utime,x_m,y_m,yaw_rad,truth_x_m,truth_y_m,truth_yaw_rad,error_m,"
             "odometry_x_m,odometry_y_m,odometry_yaw_rad\n";
      const std::optional<Pose2d> truth_anchor =
          keyframes.empty() ? std::nullopt : PoseAt(truth, keyframes.front().utime, 100000);
      for (std::size_t i = 0; i < keyframes.size(); ++i) {
        const TimedPose& k = keyframes[i];
        const std::optional<Pose2d> t = PoseAt(truth, k.utime, 100000);
        const std::optional<Pose2d> o = PoseAt(odometry, k.utime, 100000);
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
      if (!csv) throw std::runtime_error("cannot write " + FLAGS_out + "/trajectory.csv");
      std::printf("wrote %s/map.yaml, map.pgm, trajectory.csv\n", FLAGS_out.c_str());
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-slam-bench: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
      "aslam-slam-bench --world DIR --drive FILE [--config FILE] [--seed N] [--duration S]\n"
      "                 [--out DIR] [--record-log FILE [--noslam]]");
  return aslam::Run();
}
