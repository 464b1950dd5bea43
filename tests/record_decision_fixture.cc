// Records logs/decision_fixture.lcmlog for tests/utility_replay_test.cc: the
// simulator drives config/drives/test_loop.yaml through worlds/test with
// aslam-slam's, aslam-frontier's and aslam-utility's nodes on one memq bus;
// the log keeps what the frontier and utility nodes heard and said (SLAM_MAP,
// SLAM_POSE, POSE_GRAPH, FRONTIERS, UTILITY_SCORES, EXPLORE_GOAL), each
// event stamped with simulated time. Deterministic: a rerun writes the same bytes.
//   record_decision_fixture OUT.lcmlog DURATION_S

#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "common/channels.h"
#include "common/inproc_host.h"
#include "drivers/scripted_drive.h"
#include "drivers/sim_config.h"
#include "drivers/sim_node.h"
#include "frontier/frontier_config.h"
#include "frontier/frontier_node.h"
#include "slam/slam_config.h"
#include "slam/slam_node.h"
#include "utility/utility_config.h"
#include "utility/utility_node.h"
#include "worlds/worldgen.h"

namespace aslam {
namespace {

class Recorder {
 public:
  Recorder(lcm::LCM& lcm, const std::string& path, const Simulator& sim)
      : log_(path, "w"), sim_(sim) {
    lcm.subscribe(".*", &Recorder::OnMessage, this);
  }
  bool good() const { return log_.good(); }
  int64_t events() const { return events_; }

 private:
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    static const std::set<std::string> kKept = {channels::kSlamMap,   channels::kSlamPose,
                                                channels::kPoseGraph, channels::kFrontiers,
                                                channels::kUtilityScores, channels::kExploreGoal};
    if (!kKept.count(channel)) return;
    lcm::LogEvent event;
    event.eventnum = events_++;
    event.timestamp = sim_.utime();
    event.channel = channel;
    event.datalen = static_cast<int32_t>(rbuf->data_size);
    event.data = rbuf->data;
    log_.writeEvent(&event);
  }

  lcm::LogFile log_;
  const Simulator& sim_;
  int64_t events_ = 0;
};

int Run(const std::string& out, double duration_s) {
  const std::string root = ASLAM_SOURCE_DIR;
  const std::string config = root + "/config/aslam.yaml";
  const WorldInfo world = LoadWorld(root + "/worlds/test");
  Simulator sim(world.map.grid, world.start, LoadSimulatorOptionsFromFile(config));
  InProcessHost host;
  Recorder recorder(host.lcm(), out, sim);
  if (!recorder.good()) {
    std::fprintf(stderr, "record_decision_fixture: cannot write %s\n", out.c_str());
    return 1;
  }
  SimNode sim_node(host.lcm(), sim,
                   {"test", LoadScriptedDrive(root + "/config/drives/test_loop.yaml")});
  const SlamConfig slam_config = LoadSlamConfigFromFile(config);
  SlamNode slam_node(host.lcm(), slam_config.slam, slam_config.node);
  FrontierNode frontier_node(host.lcm(), LoadFrontierOptionsFromFile(config));
  UtilityNode utility_node(host.lcm(), LoadUtilityOptionsFromFile(config));
  const int64_t end_us = static_cast<int64_t>(duration_s * 1e6);
  host.Run([&] {
    sim_node.Tick();
    return sim.utime() < end_us;
  });
  std::printf("recorded %lld events, %d decisions, to %s\n",
              static_cast<long long>(recorder.events()), utility_node.decisions(), out.c_str());
  return 0;
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: record_decision_fixture OUT.lcmlog DURATION_S\n");
    return 2;
  }
  return aslam::Run(argv[1], std::atof(argv[2]));
}
