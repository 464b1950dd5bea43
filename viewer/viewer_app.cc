#include "viewer/viewer_app.h"

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <thread>

#include "common/inproc_host.h"
#include "common/lcm_util.h"
#include "common/text_format.h"
#include "viewer/viewer_lcm.h"
#include "viewer/viewer_replay.h"
#include "viewer/viewer_server.h"

namespace aslam {
namespace {

// 128 random bits as hex: the control token of a viewer reachable beyond this host.
std::string NewToken() {
  std::random_device random;
  std::string token;
  for (int i = 0; i < 4; ++i) token += Format("%08x", static_cast<unsigned>(random()));
  return token;
}

}  // namespace

void ViewerOptions::Validate() const {
  if (port < 0 || port > 65535) throw std::invalid_argument(Format("--port %d: 0..65535", port));
  if (!(rate_hz > 0.0) || rate_hz > 100.0) {
    throw std::invalid_argument(Format("--rate %g: must be in (0, 100]", rate_hz));
  }
  if (bind_address.empty()) throw std::invalid_argument("--bind: empty address");
  if (!(status_period_s >= 0.0)) throw std::invalid_argument("status period must be >= 0");
}

int RunViewer(const ViewerOptions& options, const std::atomic<bool>& stop) {
  try {
    options.Validate();
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "aslam-viewer: %s\n", e.what());
    return 2;
  }
  const bool replay = !options.log_path.empty();
  std::unique_ptr<lcm::LCM> bus;
  std::optional<InProcessHost> replay_bus;  // a replay publishes nothing anywhere
  std::string url;
  try {
    if (replay) {
      replay_bus.emplace();
    } else {
      url = ResolveLcmUrl(options.lcm_url);
      bus = OpenLcm(url);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-viewer: %s\n", e.what());
    return 1;
  }
  lcm::LCM& lcm = replay ? replay_bus->lcm() : *bus;
  ViewerNode node(lcm);

  std::unique_ptr<ViewerReplay> log;
  std::optional<ViewerReplayHooks> hooks;
  if (replay) {
    try {
      std::printf("aslam-viewer: reading %s\n", options.log_path.c_str());
      std::fflush(stdout);
      log = std::make_unique<ViewerReplay>(options.log_path);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "aslam-viewer: %s\n", e.what());
      return 1;
    }
    node.SetModel(log->ModelAt(log->end_s()));  // a finished run opens at its end
    hooks = ViewerReplayHooks{0.0, log->end_s(),
                              [&node, &log](double t_s) { node.SetModel(log->ModelAt(t_s)); }};
  }

  ViewerServerOptions server_options;
  server_options.bind_address = options.bind_address;
  server_options.port = options.port;
  server_options.allow_control = !replay;
  if (!IsLoopbackAddress(options.bind_address) && !replay) server_options.token = NewToken();
  std::unique_ptr<ViewerServer> server;
  try {
    server = std::make_unique<ViewerServer>(server_options, node, hooks);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  const std::string host = options.bind_address.find(':') != std::string::npos
                               ? "[" + options.bind_address + "]"
                               : options.bind_address;
  std::printf("aslam-viewer: open http://%s:%d/%s%s  (%s)\n", host.c_str(), server->port(),
              server_options.token.empty() ? "" : "?token=", server_options.token.c_str(),
              replay ? ("replay of " + options.log_path +
                        Format(", %.0f s, %zu messages", log->end_s(), log->events()))
                           .c_str()
                     : ("live on " + url).c_str());
  if (!server_options.token.empty()) {
    std::printf("aslam-viewer: not on loopback: control needs the token above\n");
  }
  std::fflush(stdout);

  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration<double>(1.0 / options.rate_hz);
  auto next_push = Clock::now();
  auto next_status = Clock::now() + std::chrono::duration<double>(options.status_period_s);
  int64_t bytes_at_status = 0;
  while (!stop) {
    const auto now = Clock::now();
    if (now >= next_push) {
      server->Push();
      next_push += std::chrono::duration_cast<Clock::duration>(period);
      if (next_push < now) next_push = now;  // fell behind: no burst to catch up
    }
    if (options.status_period_s > 0 && now >= next_status) {
      const int64_t bytes = server->bytes_sent();
      std::printf(
          "aslam-viewer: t=%.1f s, %d page(s), %.1f kB/s sent, %lld control request(s), "
          "%lld bad message(s)\n",
          node.t_s(), server->pages(), (bytes - bytes_at_status) / 1000.0 / options.status_period_s,
          static_cast<long long>(server->controls_sent()),
          static_cast<long long>(node.subscriptions().total_dropped()));
      std::fflush(stdout);
      bytes_at_status = bytes;
      next_status += std::chrono::duration<double>(options.status_period_s);
    }
    const auto wait =
        std::chrono::duration_cast<std::chrono::milliseconds>(next_push - Clock::now());
    const int wait_ms =
        static_cast<int>(std::max<int64_t>(0, std::min<int64_t>(wait.count(), 100)));
    if (replay) {
      std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
    } else if (lcm.handleTimeout(wait_ms) < 0 && errno != EINTR && !stop) {
      std::fprintf(stderr, "aslam-viewer: LCM failed on %s\n", url.c_str());
      return 1;
    }
  }
  std::printf("aslam-viewer: %lld bytes sent in all\n",
              static_cast<long long>(server->bytes_sent()));
  return 0;
}

}  // namespace aslam
