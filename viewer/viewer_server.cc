#include "viewer/viewer_server.h"

#include <civetweb.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/json_text.h"
#include "common/text_format.h"
#include "viewer/web_files.h"

namespace aslam {
namespace {

// The page runs only its own files and talks only to this server.
constexpr const char* kContentSecurityPolicy =
    "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; "
    "connect-src 'self' ws: wss:; base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

const WebFile* FindWebFile(const std::string& path) {
  const std::string wanted = path == "/" ? "/index.html" : path;
  for (std::size_t i = 0; i < kWebFileCount; ++i) {
    if (wanted == kWebFiles[i].path) return &kWebFiles[i];
  }
  return nullptr;
}

std::vector<std::string> Words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// Equal without an early exit, so the time a wrong token takes says nothing about the right one.
bool SameToken(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= a[i] ^ b[i];
  return diff == 0;
}

std::string ControlResult(const std::string& command, bool ok, const std::string& error) {
  return JsonObject({{"type", "\"control_result\""},
                     {"command", JsonString(command)},
                     {"ok", ok ? "true" : "false"},
                     {"error", JsonString(error)}});
}

}  // namespace

bool IsLoopbackAddress(const std::string& address) {
  return address == "localhost" || address == "::1" || address == "[::1]" ||
         address.rfind("127.", 0) == 0;
}

ViewerServer::ViewerServer(ViewerServerOptions options, ViewerNode& node,
                           std::optional<ViewerReplayHooks> replay)
    : options_(std::move(options)), node_(node), replay_(std::move(replay)) {
  mg_init_library(0);
  if (!mg_check_feature(16)) {  // 16: WebSocket support compiled in
    throw std::runtime_error("aslam-viewer: this civetweb was built without WebSocket support");
  }
  const bool ipv6 = options_.bind_address.find(':') != std::string::npos;
  const std::string host = ipv6 && options_.bind_address.front() != '['
                               ? "[" + options_.bind_address + "]"
                               : options_.bind_address;
  const std::string listen = host + ":" + std::to_string(options_.port);
  const char* config[] = {"listening_ports",      listen.c_str(), "num_threads", "4",
                          "websocket_timeout_ms", "3600000",      nullptr};
  mg_callbacks callbacks{};
  context_ = mg_start(&callbacks, this, config);
  if (context_ == nullptr) {
    throw std::runtime_error("aslam-viewer: cannot listen on " + listen +
                             " (port in use, or no such local address?)");
  }
  mg_server_port ports[4]{};
  const int n = mg_get_server_ports(context_, 4, ports);
  port_ = n > 0 ? ports[0].port : options_.port;
  mg_set_request_handler(context_, "/", &ViewerServer::OnHttp, this);
  mg_set_websocket_handler(context_, "/ws", &ViewerServer::OnWsConnect, &ViewerServer::OnWsReady,
                           &ViewerServer::OnWsData, &ViewerServer::OnWsClose, this);
}

ViewerServer::~ViewerServer() {
  if (context_ != nullptr) mg_stop(context_);
  mg_exit_library();
}

int ViewerServer::OnHttp(mg_connection* conn, void*) {
  const mg_request_info* request = mg_get_request_info(conn);
  const WebFile* file = request->local_uri ? FindWebFile(request->local_uri) : nullptr;
  if (file == nullptr || std::strcmp(request->request_method, "GET") != 0) {
    mg_send_http_error(conn, 404, "%s", "not found");
    return 404;
  }
  mg_response_header_start(conn, 200);
  mg_response_header_add(conn, "Content-Type", file->mime_type, -1);
  mg_response_header_add(conn, "Content-Length", std::to_string(file->size).c_str(), -1);
  mg_response_header_add(conn, "Content-Security-Policy", kContentSecurityPolicy, -1);
  mg_response_header_add(conn, "X-Content-Type-Options", "nosniff", -1);
  mg_response_header_add(conn, "Cache-Control", "no-store", -1);
  mg_response_header_send(conn);
  mg_write(conn, file->data, file->size);
  return 200;
}

int ViewerServer::OnWsConnect(const mg_connection*, void*) { return 0; }  // 0: accept

void ViewerServer::OnWsReady(mg_connection* conn, void* self_ptr) {
  auto* self = static_cast<ViewerServer*>(self_ptr);
  std::string hello = "{\"type\":\"hello\",\"version\":1,\"mode\":";
  hello += self->replay_ ? "\"replay\"" : "\"live\"";
  hello += Format(",\"control\":%s,\"token_required\":%s",
                  self->options_.allow_control ? "true" : "false",
                  self->options_.token.empty() ? "false" : "true");
  if (self->replay_) {
    hello += Format(",\"replay\":{\"start_s\":%.3f,\"end_s\":%.3f}", self->replay_->start_s,
                    self->replay_->end_s);
  }
  hello += "}";
  std::lock_guard<std::mutex> lock(self->mutex_);
  self->pages_[conn] = Page{};
  self->Send(conn, hello);
}

int ViewerServer::OnWsData(mg_connection* conn, int bits, char* data, size_t length,
                           void* self_ptr) {
  auto* self = static_cast<ViewerServer*>(self_ptr);
  const int opcode = bits & 0x0f;
  if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
  if (opcode != MG_WEBSOCKET_OPCODE_TEXT || length > 4096) return 1;  // ignored
  const mg_request_info* info = mg_get_request_info(conn);
  const std::string answer =
      self->HandleRequest(std::string(data, length), info ? info->remote_addr : "?");
  if (!answer.empty()) {
    std::lock_guard<std::mutex> lock(self->mutex_);
    self->Send(conn, answer);
  }
  return 1;
}

void ViewerServer::OnWsClose(const mg_connection* conn, void* self_ptr) {
  auto* self = static_cast<ViewerServer*>(self_ptr);
  std::lock_guard<std::mutex> lock(self->mutex_);
  self->pages_.erase(const_cast<mg_connection*>(conn));
}

std::string ViewerServer::HandleRequest(const std::string& request, const std::string& peer) {
  const std::vector<std::string> words = Words(request);
  if (words.empty()) return "";
  if (words[0] == "control") {
    const std::string name = words.size() >= 2 ? words[1] : "";
    const std::optional<ExploreCommand> command = ParseExploreCommand(name);
    if (!command) {
      return ControlResult(name, false,
                           "unknown command: expected pause, resume, stop or "
                           "return_home");
    }
    if (!options_.allow_control) return ControlResult(name, false, "control is off (a replay)");
    if (!options_.token.empty() && (words.size() < 3 || !SameToken(words[2], options_.token))) {
      return ControlResult(name, false, "wrong or missing token");
    }
    node_.SendControl(*command, "aslam-viewer page at " + peer);
    ++controls_sent_;
    return ControlResult(name, true, "");
  }
  if (words[0] == "seek" && replay_ && words.size() == 2) {
    char* end = nullptr;
    const double t_s = std::strtod(words[1].c_str(), &end);
    if (end == words[1].c_str() || *end != '\0' || !std::isfinite(t_s)) return "";
    replay_->seek(std::min(std::max(t_s, replay_->start_s), replay_->end_s));
    ResetPages();
  }
  return "";
}

void ViewerServer::Send(mg_connection* conn, const std::string& text) {
  const int written = mg_websocket_write(conn, MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
  if (written > 0) bytes_sent_ += written;
}

void ViewerServer::Push() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& [conn, page] : pages_) {
    const std::string frame = node_.Update(&page.cursor);
    if (!frame.empty()) Send(conn, frame);
  }
}

void ViewerServer::ResetPages() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& [conn, page] : pages_) page.cursor.reset_pending = true;
}

int ViewerServer::pages() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(pages_.size());
}

}  // namespace aslam
