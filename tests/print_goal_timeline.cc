// What a run's lcm log says about its goals, one line per event in simulated time: every
// decision (the robot's position, eligible/all frontiers, the chosen one and the best
// rejected one), every EXPLORE_GOAL, every change of the navigator's state for a goal (with
// its detail) and every change of the exploration's state. The process tests print it when
// an exploration fails, so a rare failure on CI can be read from its output.
//   print_goal_timeline RUN/run.lcmlog

#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/utility_scores_t.hpp"
#include "common/channels.h"
#include "navigation/nav_lcm.h"
#include "utility/utility_lcm.h"

namespace {

template <typename Message>
bool Decode(const lcm::LogEvent& event, Message* message) {
  return message->decode(event.data, 0, event.datalen) >= 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: print_goal_timeline RUN/run.lcmlog\n");
    return 2;
  }
  lcm::LogFile log(argv[1], "r");
  if (!log.good()) {
    std::fprintf(stderr, "print_goal_timeline: cannot read %s\n", argv[1]);
    return 1;
  }
  double robot_x = NAN, robot_y = NAN;  // SLAM's latest pose, in "map" like the goals
  int64_t nav_goal = -2;                // no NAV_STATUS yet
  std::optional<aslam::NavState> nav_state;
  std::optional<aslam::ExploreState> explore_state;
  std::printf("goal timeline of %s (t = simulated s; positions in the map frame)\n", argv[1]);
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    const std::string channel = event->channel;
    if (channel == aslam::channels::kSlamPose) {
      aslam::pose_t m;
      if (Decode(*event, &m)) robot_x = m.pose.x_m, robot_y = m.pose.y_m;
    } else if (channel == aslam::channels::kUtilityScores) {
      aslam::utility_scores_t m;
      if (!Decode(*event, &m)) continue;
      int eligible = 0;
      const aslam::frontier_score_t* chosen = nullptr;
      const aslam::frontier_score_t* runner_up = nullptr;
      for (const aslam::frontier_score_t& s : m.scores) {
        if (!s.eligible) continue;
        ++eligible;
        if (s.chosen) {
          chosen = &s;
        } else if (runner_up == nullptr || s.total > runner_up->total) {
          runner_up = &s;
        }
      }
      std::printf("%8.2f decision %ld  robot (%.2f, %.2f)  eligible %d of %d", m.utime * 1e-6,
                  static_cast<long>(m.decision_id), m.robot_pose.x_m, m.robot_pose.y_m, eligible,
                  m.num_scores);
      if (chosen != nullptr) {
        std::printf("  chose frontier %d at (%.2f, %.2f), path %.2f m, total %.4g",
                    chosen->frontier_id, chosen->target_x_m, chosen->target_y_m,
                    chosen->path_length_m, chosen->total);
      }
      if (runner_up != nullptr) {
        std::printf("  | next frontier %d at (%.2f, %.2f), path %.2f m, total %.4g",
                    runner_up->frontier_id, runner_up->target_x_m, runner_up->target_y_m,
                    runner_up->path_length_m, runner_up->total);
      }
      std::printf("\n");
    } else if (channel == aslam::channels::kExploreGoal) {
      aslam::explore_goal_t m;
      if (!Decode(*event, &m)) continue;
      if (m.cancel) {
        std::printf("%8.2f goal %ld cancelled\n", m.utime * 1e-6, static_cast<long>(m.goal_id));
      } else {
        std::printf("%8.2f goal %ld to (%.2f, %.2f) for frontier %d\n", m.utime * 1e-6,
                    static_cast<long>(m.goal_id), m.x_m, m.y_m, m.frontier_id);
      }
    } else if (channel == aslam::channels::kNavStatus) {
      aslam::nav_status_t m;
      if (!Decode(*event, &m)) continue;
      const std::optional<aslam::NavStatus> status = aslam::FromLcm(m);
      if (!status || (status->goal_id == nav_goal && status->state == nav_state)) continue;
      nav_goal = status->goal_id;
      nav_state = status->state;
      std::printf("%8.2f   nav goal %ld %s  robot (%.2f, %.2f)%s%s\n", status->utime * 1e-6,
                  static_cast<long>(status->goal_id), aslam::NavStateName(status->state), robot_x,
                  robot_y, status->detail.empty() ? "" : ": ", status->detail.c_str());
    } else if (channel == aslam::channels::kExploreStatus) {
      aslam::explore_status_t m;
      if (!Decode(*event, &m)) continue;
      const std::optional<aslam::ExploreState> state = aslam::ExploreStateFromLcm(m.state);
      if (!state || state == explore_state) continue;
      explore_state = state;
      std::printf("%8.2f exploration %s: %d frontiers, %d eligible%s%s\n", m.utime * 1e-6,
                  aslam::ExploreStateName(*state), m.num_frontiers, m.num_eligible,
                  m.detail.empty() ? "" : ": ", m.detail.c_str());
    }
  }
  return 0;
}
