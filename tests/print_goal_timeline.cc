// What a run's lcm log says about its goals, one line per event in simulated time: every
// decision (the robot's position, eligible/all frontiers, the chosen one and the best
// rejected one), every EXPLORE_GOAL, every change of the navigator's state for a goal (with
// its detail) and every change of the exploration's state. The process tests print it when
// an exploration fails, so a rare failure on CI can be read from its output.
//   print_goal_timeline RUN/run.lcmlog

#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/utility_scores_t.hpp"

namespace {

const char* NavStateName(int state) {
  switch (state) {
    case aslam::nav_status_t::STATE_IDLE: return "idle";
    case aslam::nav_status_t::STATE_ACTIVE: return "active";
    case aslam::nav_status_t::STATE_REACHED: return "reached";
    case aslam::nav_status_t::STATE_FAILED: return "failed";
    case aslam::nav_status_t::STATE_UNREACHABLE: return "unreachable";
    default: return "?";
  }
}

const char* ExploreStateName(int state) {
  switch (state) {
    case aslam::explore_status_t::STATE_WAITING: return "waiting";
    case aslam::explore_status_t::STATE_EXPLORING: return "exploring";
    case aslam::explore_status_t::STATE_DONE: return "done";
    default: return "?";
  }
}

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
  int64_t nav_goal = -2, explore_state = -1;
  int nav_state = -1;
  std::printf("goal timeline of %s (t = simulated s; positions in the map frame)\n", argv[1]);
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    const std::string channel = event->channel;
    if (channel == "SLAM_POSE") {
      aslam::pose_t m;
      if (Decode(*event, &m)) robot_x = m.pose.x_m, robot_y = m.pose.y_m;
    } else if (channel == "UTILITY_SCORES") {
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
    } else if (channel == "EXPLORE_GOAL") {
      aslam::explore_goal_t m;
      if (!Decode(*event, &m)) continue;
      if (m.cancel) {
        std::printf("%8.2f goal %ld cancelled\n", m.utime * 1e-6, static_cast<long>(m.goal_id));
      } else {
        std::printf("%8.2f goal %ld to (%.2f, %.2f) for frontier %d\n", m.utime * 1e-6,
                    static_cast<long>(m.goal_id), m.x_m, m.y_m, m.frontier_id);
      }
    } else if (channel == "NAV_STATUS") {
      aslam::nav_status_t m;
      if (!Decode(*event, &m) || (m.goal_id == nav_goal && m.state == nav_state)) continue;
      nav_goal = m.goal_id;
      nav_state = m.state;
      std::printf("%8.2f   nav goal %ld %s  robot (%.2f, %.2f)%s%s\n", m.utime * 1e-6,
                  static_cast<long>(m.goal_id), NavStateName(m.state), robot_x, robot_y,
                  m.detail.empty() ? "" : ": ", m.detail.c_str());
    } else if (channel == "EXPLORE_STATUS") {
      aslam::explore_status_t m;
      if (!Decode(*event, &m) || m.state == explore_state) continue;
      explore_state = m.state;
      std::printf("%8.2f exploration %s: %d frontiers, %d eligible%s%s\n", m.utime * 1e-6,
                  ExploreStateName(m.state), m.num_frontiers, m.num_eligible,
                  m.detail.empty() ? "" : ": ", m.detail.c_str());
    }
  }
  return 0;
}
