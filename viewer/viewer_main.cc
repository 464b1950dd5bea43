// aslam-viewer: the map, pose graph, frontiers and why a goal won, live in a browser; and
// pause, resume, stop or send the robot home. See README "Viewer" and viewer/protocol.md.

#include <atomic>
#include <csignal>

#include <gflags/gflags.h>

#include "common/flags.h"
#include "viewer/viewer_app.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(log, "", "replay this lcm log (a run folder's run.lcmlog) with a time slider");
DEFINE_string(bind, "127.0.0.1",
              "address to serve on; beyond loopback, control needs the printed token");
DEFINE_int32(port, 8080, "HTTP and WebSocket port (0: any free port)");
DEFINE_double(rate, 2.0, "updates per second to each page");

namespace {
std::atomic<bool> g_stop{false};
}

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
                    "aslam-viewer [--lcm-url URL | --log FILE] [--bind ADDR] [--port N] "
                    "[--rate HZ]: the exploration in a browser.");
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::signal(SIGTERM, [](int) { g_stop = true; });
  aslam::ViewerOptions options;
  options.lcm_url = FLAGS_lcm_url;
  options.log_path = FLAGS_log;
  options.bind_address = FLAGS_bind;
  options.port = FLAGS_port;
  options.rate_hz = FLAGS_rate;
  return aslam::RunViewer(options, g_stop);
}
