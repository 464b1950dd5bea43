// Replays logs/decision_fixture.lcmlog (recorded by logs/record_decision_fixture.sh:
// the simulator driving the ring loop of worlds/test with SLAM, frontier and
// utility nodes in-process). The recorded SLAM_MAP, SLAM_POSE and POSE_GRAPH
// are published in recorded order, each dispatched before the next, into fresh
// FrontierNode and UtilityNode; what they publish must be the recorded
// FRONTIERS, UTILITY_SCORES and EXPLORE_GOAL: the same frontiers, the same
// terms for every frontier, the same winners.

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "aslam/explore_goal_t.hpp"
#include "aslam/frontier_list_t.hpp"
#include "aslam/utility_scores_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/lcm_util.h"
#include "frontier/frontier_config.h"
#include "frontier/frontier_node.h"
#include "tests/decision_fixture.h"
#include "utility/utility_config.h"
#include "utility/utility_node.h"

namespace aslam {
namespace {

const std::string kRoot = ASLAM_SOURCE_DIR;
const std::string kConfig = kRoot + "/config/aslam.yaml";

struct Outputs {
  std::vector<frontier_list_t> frontiers;
  std::vector<utility_scores_t> scores;
  std::vector<explore_goal_t> goals;
};

template <typename MsgT>
MsgT Decode(const lcm::LogEvent& event) {
  MsgT msg{};
  EXPECT_EQ(msg.decode(event.data, 0, event.datalen), event.datalen) << event.channel;
  return msg;
}

TEST(UtilityReplay, SameFrontiersScoresAndGoalsAsRecorded) {
  lcm::LogFile log(kRoot + "/logs/decision_fixture.lcmlog", "r");
  ASSERT_TRUE(log.good());
  InProcessHost host;
  // Frontier and utility plan as the shipped navigator does, robot included.
  const NavOptions nav = LoadNavOptionsFromFile(kConfig);
  FrontierNode frontier_node(host.lcm(),
                             LoadFrontierOptions(ConfigReader::FromFile(kConfig, "frontier"), nav));
  UtilityNode utility_node(host.lcm(), DecisionFixtureUtilityOptions(kConfig, nav));
  Outputs replayed, recorded;
  Subscriptions capture(host.lcm());
  capture.Add<frontier_list_t>(channels::kFrontiers, [&](const frontier_list_t& m) {
    replayed.frontiers.push_back(m);
    return true;
  });
  capture.Add<utility_scores_t>(channels::kUtilityScores, [&](const utility_scores_t& m) {
    replayed.scores.push_back(m);
    return true;
  });
  capture.Add<explore_goal_t>(channels::kExploreGoal, [&](const explore_goal_t& m) {
    replayed.goals.push_back(m);
    return true;
  });

  int inputs = 0;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    const std::string& channel = event->channel;
    if (channel == channels::kSlamMap || channel == channels::kSlamPose ||
        channel == channels::kPoseGraph) {
      host.lcm().publish(channel, event->data, event->datalen);
      host.DispatchPending();
      ++inputs;
    } else if (channel == channels::kFrontiers) {
      recorded.frontiers.push_back(Decode<frontier_list_t>(*event));
    } else if (channel == channels::kUtilityScores) {
      recorded.scores.push_back(Decode<utility_scores_t>(*event));
    } else if (channel == channels::kExploreGoal) {
      recorded.goals.push_back(Decode<explore_goal_t>(*event));
    }
  }
  EXPECT_EQ(frontier_node.subscriptions().total_dropped(), 0);
  EXPECT_EQ(utility_node.subscriptions().total_dropped(), 0);
  // The fixture must hold real decisions for this to mean anything.
  ASSERT_GT(inputs, 100);
  ASSERT_GE(recorded.scores.size(), 2u);
  ASSERT_GE(recorded.goals.size(), 2u);

  ASSERT_EQ(replayed.frontiers.size(), recorded.frontiers.size());
  for (std::size_t i = 0; i < recorded.frontiers.size(); ++i) {
    const frontier_list_t& a = replayed.frontiers[i];
    const frontier_list_t& b = recorded.frontiers[i];
    EXPECT_EQ(a.map_revision, b.map_revision);
    ASSERT_EQ(a.num_frontiers, b.num_frontiers) << "list " << i;
    for (int f = 0; f < a.num_frontiers; ++f) {
      EXPECT_EQ(a.frontiers[f].id, b.frontiers[f].id);
      EXPECT_EQ(a.frontiers[f].size_cells, b.frontiers[f].size_cells);
      EXPECT_DOUBLE_EQ(a.frontiers[f].target_x_m, b.frontiers[f].target_x_m);
      EXPECT_DOUBLE_EQ(a.frontiers[f].target_y_m, b.frontiers[f].target_y_m);
    }
  }

  ASSERT_EQ(replayed.scores.size(), recorded.scores.size());
  for (std::size_t i = 0; i < recorded.scores.size(); ++i) {
    const utility_scores_t& a = replayed.scores[i];
    const utility_scores_t& b = recorded.scores[i];
    SCOPED_TRACE("decision " + std::to_string(b.decision_id));
    EXPECT_EQ(a.decision_id, b.decision_id);
    EXPECT_EQ(a.method, b.method);
    EXPECT_EQ(a.graph_nodes, b.graph_nodes);
    EXPECT_EQ(a.chosen_frontier_id, b.chosen_frontier_id);
    ASSERT_EQ(a.num_scores, b.num_scores);
    for (int s = 0; s < a.num_scores; ++s) {
      EXPECT_EQ(a.scores[s].frontier_id, b.scores[s].frontier_id);
      EXPECT_EQ(a.scores[s].eligible, b.scores[s].eligible);
      EXPECT_EQ(a.scores[s].chosen, b.scores[s].chosen);
      // U1 and U2 to 1e-12 relative: the same terms up to rounding (the edge weights'
      // determinant and eigenvalue formulas differ in the last bits), nothing more.
      EXPECT_NEAR(a.scores[s].u1, b.scores[s].u1, 1e-12 * std::abs(b.scores[s].u1));
      EXPECT_NEAR(a.scores[s].u2, b.scores[s].u2, 1e-12 * std::abs(b.scores[s].u2));
      EXPECT_DOUBLE_EQ(a.scores[s].path_length_m, b.scores[s].path_length_m);
    }
  }

  ASSERT_EQ(replayed.goals.size(), recorded.goals.size());
  for (std::size_t i = 0; i < recorded.goals.size(); ++i) {
    EXPECT_EQ(replayed.goals[i].goal_id, recorded.goals[i].goal_id);
    EXPECT_EQ(replayed.goals[i].frontier_id, recorded.goals[i].frontier_id);
    EXPECT_GE(recorded.goals[i].frontier_id, 0);
    EXPECT_DOUBLE_EQ(replayed.goals[i].x_m, recorded.goals[i].x_m);
    EXPECT_DOUBLE_EQ(replayed.goals[i].y_m, recorded.goals[i].y_m);
  }
}

}  // namespace
}  // namespace aslam
