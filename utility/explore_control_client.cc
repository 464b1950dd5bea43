#include "utility/explore_control_client.h"

#include <chrono>

#include "aslam/explore_control_t.hpp"
#include "common/channels.h"
#include "common/text_format.h"
#include "utility/utility_lcm.h"

namespace aslam {

std::optional<explore_status_t> SendExploreControl(lcm::LCM& lcm, ExploreCommand command,
                                                   const std::string& source, double wait_s) {
  std::optional<explore_status_t> answer;
  lcm::Subscription* subscription = lcm.subscribeFunction(
      channels::kExploreStatus,
      +[](const lcm::ReceiveBuffer*, const std::string&, const explore_status_t* msg,
          std::optional<explore_status_t>* out) {
        if (!*out) *out = *msg;
      },
      &answer);
  const explore_control_t msg = ExploreControlMessage(command, source);
  lcm.publish(channels::kExploreControl, &msg);
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(wait_s);
  while (!answer) {
    const auto left_ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left_ms <= 0) break;
    if (lcm.handleTimeout(static_cast<int>(std::min<int64_t>(left_ms, 100))) < 0) break;
  }
  lcm.unsubscribe(subscription);
  return answer;
}

std::string DescribeExploreStatus(const explore_status_t& status) {
  const std::optional<ExploreState> state = ExploreStateFromLcm(status.state);
  return Format("%s: %s (%s, %d decisions, %d goals reached, %d failed)",
                state ? ExploreStateName(*state) : "unknown state", status.detail.c_str(),
                status.method.c_str(), status.decisions, status.goals_reached, status.goals_failed);
}

}  // namespace aslam
