#pragma once

// aslam-viewer's HTTP and WebSocket server, on civetweb (Debian's libcivetweb): serves the
// page (viewer/web/, built into the binary) at / and speaks viewer/protocol.md on /ws. Each
// connected page has its own ViewerCursor, so it gets only what changed since its last frame.

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "viewer/viewer_lcm.h"

struct mg_connection;
struct mg_context;

namespace aslam {

struct ViewerServerOptions {
  std::string bind_address = "127.0.0.1";
  int port = 8080;  // 0: any free port (port() tells which)
  // Required in control requests when not empty (a viewer reachable beyond this host).
  std::string token;
  bool allow_control = true;  // false for replays: nothing to control
};

// Replay mode: the slider's range and what a seek does.
struct ViewerReplayHooks {
  double start_s = 0.0;
  double end_s = 0.0;
  // Shows the run at t_s (log time); called from a server thread.
  std::function<void(double t_s)> seek;
};

// True for 127.0.0.0/8, ::1 and "localhost".
bool IsLoopbackAddress(const std::string& address);

class ViewerServer {
 public:
  // Throws std::runtime_error naming the address and port when it cannot listen.
  ViewerServer(ViewerServerOptions options, ViewerNode& node,
               std::optional<ViewerReplayHooks> replay = std::nullopt);
  ~ViewerServer();
  ViewerServer(const ViewerServer&) = delete;
  ViewerServer& operator=(const ViewerServer&) = delete;

  int port() const { return port_; }
  // Sends every connected page its update frame (call at the viewer's rate).
  void Push();
  // After a seek: every page starts afresh with its next frame.
  void ResetPages();

  int pages() const;
  int64_t bytes_sent() const { return bytes_sent_; }
  int64_t controls_sent() const { return controls_sent_; }

 private:
  struct Page {
    ViewerCursor cursor;
  };
  static int OnHttp(mg_connection* conn, void* self);
  static int OnWsConnect(const mg_connection* conn, void* self);
  static void OnWsReady(mg_connection* conn, void* self);
  static int OnWsData(mg_connection* conn, int bits, char* data, size_t length, void* self);
  static void OnWsClose(const mg_connection* conn, void* self);
  // Sends one text frame (with mutex_ held).
  void Send(mg_connection* conn, const std::string& text);
  std::string HandleRequest(const std::string& request, const std::string& peer);

  const ViewerServerOptions options_;
  ViewerNode& node_;
  const std::optional<ViewerReplayHooks> replay_;
  mg_context* context_ = nullptr;
  int port_ = 0;
  mutable std::mutex mutex_;  // pages_ and every write
  std::map<mg_connection*, Page> pages_;
  std::atomic<int64_t> bytes_sent_{0};
  std::atomic<int64_t> controls_sent_{0};
};

}  // namespace aslam
