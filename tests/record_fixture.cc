// Records the replay fixtures of worlds/test, every node in one process on
// memq, each event stamped with simulated time:
//   decision:    the simulator follows config/drives/test_loop.yaml with the
//                slam, frontier and utility nodes; keeps what frontier and
//                utility heard and said (SLAM_MAP, SLAM_POSE, POSE_GRAPH,
//                FRONTIERS, UTILITY_SCORES, EXPLORE_GOAL) for
//                tests/utility_replay_test.cc.
//   exploration: the whole stack explores (nav drives); keeps ODOMETRY,
//                LIDAR_SCAN and POSE_GRAPH for tests/exploration_replay_test.cc.
// Deterministic apart from UTILITY_SCORES.compute_ms (wall clock).
//   record_fixture decision|exploration OUT.lcmlog DURATION_S

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <set>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/lcm_log_writer.h"
#include "common/robot_config.h"
#include "common/world_file.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/sim_config.h"
#include "drivers/sim/sim_node.h"
#include "frontier/frontier_config.h"
#include "frontier/frontier_node.h"
#include "navigation/nav_config.h"
#include "navigation/nav_node.h"
#include "slam/slam_config.h"
#include "slam/slam_node.h"
#include "tests/decision_fixture.h"
#include "utility/utility_config.h"
#include "utility/utility_node.h"

namespace aslam {
namespace {

// Records the chosen channels as they are published, stamped with simulated time.
class Recorder {
 public:
  Recorder(lcm::LCM& lcm, const std::string& path, const Simulator& sim,
           std::set<std::string> channels)
      : log_(path), sim_(sim), channels_(std::move(channels)) {
    lcm.subscribe(".*", &Recorder::OnMessage, this);
  }
  int64_t events() const { return log_.events(); }

 private:
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    if (!channels_.count(channel)) return;
    log_.WriteBytes(channel, sim_.utime(), rbuf->data, static_cast<int32_t>(rbuf->data_size));
  }

  LcmLogWriter log_;
  const Simulator& sim_;
  std::set<std::string> channels_;
};

int Run(const std::string& kind, const std::string& out, double duration_s) {
  const bool exploration = kind == "exploration";
  if (!exploration && kind != "decision") {
    std::fprintf(stderr, "record_fixture: unknown kind '%s' (decision or exploration)\n",
                 kind.c_str());
    return 2;
  }
  const std::string root = ASLAM_SOURCE_DIR;
  const std::string config = root + "/config/aslam.yaml";
  const WorldInfo world = LoadWorld(root + "/worlds/test");
  // The robot once, for the simulator and the navigator, whose planning frontier and utility share.
  const RobotOptions robot = LoadRobotOptionsFromFile(config);
  const NavOptions nav_options = LoadNavOptions(ConfigReader::FromFile(config, "nav"), robot);
  Simulator sim(world.map.grid, world.start,
                LoadSimulatorOptions(ConfigReader::FromFile(config, "sim"), robot));
  InProcessHost host;
  Recorder recorder(
      host.lcm(), out, sim,
      exploration
          ? std::set<std::string>{channels::kOdometry, channels::kLidarScan, channels::kPoseGraph}
          : std::set<std::string>{channels::kSlamMap, channels::kSlamPose, channels::kPoseGraph,
                                  channels::kFrontiers, channels::kUtilityScores,
                                  channels::kExploreGoal});
  SimNodeOptions sim_options{"test", std::nullopt};
  if (!exploration) sim_options.drive = LoadScriptedDrive(root + "/config/drives/test_loop.yaml");
  SimNode sim_node(host.lcm(), sim, sim_options);
  const SlamConfig slam_config = LoadSlamConfigFromFile(config);
  SlamNode slam_node(host.lcm(), slam_config.slam, slam_config.node);
  FrontierNode frontier_node(
      host.lcm(), LoadFrontierOptions(ConfigReader::FromFile(config, "frontier"), nav_options));
  UtilityNode utility_node(host.lcm(), DecisionFixtureUtilityOptions(config, nav_options));
  std::optional<NavNode> nav_node;
  if (exploration) nav_node.emplace(host.lcm(), nav_options);
  const int64_t end_us = static_cast<int64_t>(duration_s * 1e6);
  host.Run([&] {
    sim_node.Tick();
    return sim.utime() < end_us;
  });
  std::printf("recorded %lld events, %d decisions, %zu keyframes, %lld loop closures, to %s\n",
              static_cast<long long>(recorder.events()), utility_node.decisions(),
              slam_node.slam().graph().nodes.size(),
              static_cast<long long>(slam_node.slam().counters().loop_closures_accepted),
              out.c_str());
  return 0;
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: record_fixture decision|exploration OUT.lcmlog DURATION_S\n");
    return 2;
  }
  try {
    return aslam::Run(argv[1], argv[2], std::atof(argv[3]));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "record_fixture: %s\n", e.what());
    return 1;
  }
}
