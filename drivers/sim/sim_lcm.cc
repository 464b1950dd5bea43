#include "drivers/sim/sim_lcm.h"

namespace aslam {

sim_status_t ToLcm(const SimStatus& status, const SimStatusExtras& extras) {
  sim_status_t msg{};
  msg.utime = status.utime;
  msg.world = extras.world;
  msg.seed = static_cast<int64_t>(extras.seed);
  msg.ticks = status.ticks;
  msg.real_time_factor = extras.real_time_factor;
  msg.collisions = static_cast<int32_t>(status.collisions);
  msg.in_collision = status.in_collision;
  msg.command_stale = status.command_stale;
  msg.scans_published = status.scans_published;
  msg.commands_received = extras.commands_received;
  msg.messages_dropped = extras.messages_dropped;
  return msg;
}

}  // namespace aslam
