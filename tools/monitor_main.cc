// aslam-monitor: a text-mode view of an LCM bus, like `rostopic hz` for
// every channel at once: message rate, bandwidth and type per channel, plus
// the latest simulator status. For a GUI with every field, use scripts/spy.

#include <gflags/gflags.h>

#include "common/flags.h"
#include "tools/monitor.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_double(duration, 0, "seconds to listen; 0 = until Ctrl-C");
DEFINE_double(period, 1.0, "seconds between reports");

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
                    "aslam-monitor [--lcm-url URL] [--duration S]: message rate and type per "
                    "channel.\nExits 3 if no message was heard.");
  aslam::MonitorOptions options;
  options.lcm_url = FLAGS_lcm_url;
  options.duration_s = FLAGS_duration;
  options.period_s = FLAGS_period;
  return aslam::RunMonitor(options);
}
