#include "drivers/io/driver_status_lcm.h"

#include "common/channels.h"

namespace aslam {

driver_status_t ToLcm(const DriverStatus& s) {
  driver_status_t msg;
  msg.utime = s.utime;
  msg.driver = s.driver;
  msg.device = s.device;
  msg.connected = s.connected;
  msg.messages = s.messages;
  msg.rate_hz = s.rate_hz;
  msg.clock_offset_ms = s.clock_offset_ms;
  msg.clock_jitter_ms = s.clock_jitter_ms;
  msg.errors = s.errors;
  msg.reconnects = s.reconnects;
  msg.detail = s.detail;
  return msg;
}

void PublishDriverStatus(lcm::LCM& lcm, const DriverStatus& status) {
  const driver_status_t msg = ToLcm(status);
  lcm.publish(channels::kDriverStatus, &msg);
}

}  // namespace aslam
