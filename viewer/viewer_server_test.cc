#include "viewer/viewer_server.h"

#include <civetweb.h>

#include <chrono>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "aslam/explore_control_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/lcm_log_writer.h"
#include "common/test_temp_dir.h"
#include "frontier/frontier_lcm.h"
#include "viewer/viewer_lcm.h"
#include "viewer/viewer_replay.h"
#include "viewer/viewer_testing.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;

struct HttpResponse {
  int status = 0;
  std::string content_security_policy;
  std::string body;
};

HttpResponse Get(int port, const std::string& path) {
  char error[256] = "";
  mg_connection* conn = mg_download("127.0.0.1", port, 0, error, sizeof error,
                                    "GET %s HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n", path.c_str());
  HttpResponse response;
  if (conn == nullptr) {
    ADD_FAILURE() << "GET " << path << ": " << error;
    return response;
  }
  const mg_response_info* info = mg_get_response_info(conn);
  response.status = info->status_code;
  for (int i = 0; i < info->num_headers; ++i) {
    if (std::strcmp(info->http_headers[i].name, "Content-Security-Policy") == 0) {
      response.content_security_policy = info->http_headers[i].value;
    }
  }
  char buffer[4096];
  for (int n; (n = mg_read(conn, buffer, sizeof buffer)) > 0;) response.body.append(buffer, n);
  mg_close_connection(conn);
  return response;
}

// A page as the server sees one: a WebSocket client on /ws recording every text frame
// (compacted).
class Page {
 public:
  explicit Page(int port) {
    char error[256] = "";
    conn_ = mg_connect_websocket_client("127.0.0.1", port, 0, error, sizeof error, "/ws", nullptr,
                                        &Page::OnData, nullptr, this);
    EXPECT_NE(conn_, nullptr) << error;
  }
  ~Page() {
    if (conn_) mg_close_connection(conn_);
  }
  void Send(const std::string& text) {
    mg_websocket_client_write(conn_, MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
  }
  // The first frame from `from` on that holds `needle`, waiting up to 5 s; "" if none came.
  std::string WaitFor(const std::string& needle, std::size_t* from = nullptr) {
    std::unique_lock<std::mutex> lock(mutex_);
    std::size_t start = from ? *from : 0;
    std::string found;
    cv_.wait_for(lock, std::chrono::seconds(5), [&] {
      for (std::size_t i = start; i < frames_.size(); ++i) {
        if (frames_[i].find(needle) != std::string::npos) {
          found = frames_[i];
          if (from) *from = i + 1;
          return true;
        }
      }
      return false;
    });
    return found;
  }

 private:
  static int OnData(mg_connection*, int bits, char* data, size_t length, void* self_ptr) {
    auto* self = static_cast<Page*>(self_ptr);
    if ((bits & 0x0f) == MG_WEBSOCKET_OPCODE_TEXT) {
      std::lock_guard<std::mutex> lock(self->mutex_);
      self->frames_.push_back(Compact(std::string(data, length)));
      self->cv_.notify_all();
    }
    return 1;
  }
  mg_connection* conn_ = nullptr;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<std::string> frames_;
};

FrontierList Frontiers(int64_t utime, int count) {
  FrontierList list;
  list.utime = utime;
  for (int id = 0; id < count; ++id) {
    Frontier f;
    f.id = 10 + id;
    f.points_m = {{1.0 * id, 2.0}};
    f.centroid_m = f.target_m = {1.0 * id, 2.0};
    list.frontiers.push_back(f);
  }
  return list;
}

ViewerServerOptions AnyPort() {
  ViewerServerOptions options;
  options.port = 0;
  return options;
}

TEST(ViewerServer, ServesThePageUnderItsPolicyAndNothingElse) {
  InProcessHost host;
  ViewerNode node(host.lcm());
  ViewerServer server(AnyPort(), node);
  ASSERT_GT(server.port(), 0);
  const HttpResponse page = Get(server.port(), "/");
  EXPECT_EQ(page.status, 200);
  EXPECT_THAT(page.body, HasSubstr("viewer.js"));
  EXPECT_THAT(page.content_security_policy, HasSubstr("script-src 'self'"));
  EXPECT_EQ(Get(server.port(), "/viewer.js").status, 200);
  EXPECT_EQ(Get(server.port(), "/viewer.css").status, 200);
  EXPECT_EQ(Get(server.port(), "/../viewer_server.cc").status, 404);
  EXPECT_EQ(Get(server.port(), "/etc/passwd").status, 404);
}

TEST(ViewerServer, APageGetsHelloThenWhatChangedAndItsControlGoesOnTheBus) {
  InProcessHost host;
  ViewerNode node(host.lcm());
  ViewerServer server(AnyPort(), node);
  std::vector<explore_control_t> controls;
  Subscriptions listener(host.lcm());
  listener.Add<explore_control_t>(channels::kExploreControl, [&](const explore_control_t& m) {
    controls.push_back(m);
    return true;
  });
  Page page(server.port());
  EXPECT_THAT(page.WaitFor("hello"), HasSubstr("\"mode\":\"live\",\"control\":true,"
                                               "\"token_required\":false"));

  const frontier_list_t msg = ToLcm(Frontiers(3'000'000, 2));
  host.lcm().publish(channels::kFrontiers, &msg);
  host.DispatchPending();
  server.Push();
  std::size_t next = 0;
  const std::string update = page.WaitFor("\"frontiers\"", &next);
  EXPECT_THAT(update, HasSubstr("\"id\":10"));
  EXPECT_THAT(update, HasSubstr("\"id\":11"));
  server.Push();  // nothing changed: no frame
  EXPECT_EQ(server.pages(), 1);

  page.Send("control pause");
  EXPECT_THAT(page.WaitFor("control_result"), HasSubstr("\"command\":\"pause\",\"ok\":true"));
  host.DispatchPending();
  ASSERT_EQ(controls.size(), 1u);
  EXPECT_EQ(controls[0].command, explore_control_t::PAUSE);
  EXPECT_THAT(controls[0].source, HasSubstr("aslam-viewer"));

  page.Send("control dance");
  EXPECT_THAT(page.WaitFor("\"dance\""), HasSubstr("\"ok\":false"));
  host.DispatchPending();
  EXPECT_EQ(controls.size(), 1u);
  EXPECT_EQ(server.controls_sent(), 1);
  EXPECT_GT(server.bytes_sent(), 0);
}

TEST(ViewerServer, BeyondLoopbackControlNeedsTheToken) {
  InProcessHost host;
  ViewerNode node(host.lcm());
  ViewerServerOptions options = AnyPort();
  options.token = "0123abcd";
  ViewerServer server(options, node);
  Page page(server.port());
  EXPECT_THAT(page.WaitFor("hello"), HasSubstr("\"token_required\":true"));
  std::size_t next = 0;
  page.Send("control stop");
  EXPECT_THAT(page.WaitFor("control_result", &next), HasSubstr("wrong or missing token"));
  page.Send("control stop 0123abce");
  EXPECT_THAT(page.WaitFor("control_result", &next), HasSubstr("wrong or missing token"));
  page.Send("control stop 0123abcd");
  EXPECT_THAT(page.WaitFor("control_result", &next), HasSubstr("\"ok\":true"));
  EXPECT_EQ(server.controls_sent(), 1);

  EXPECT_TRUE(IsLoopbackAddress("127.0.0.1"));
  EXPECT_TRUE(IsLoopbackAddress("::1"));
  EXPECT_FALSE(IsLoopbackAddress("0.0.0.0"));
  EXPECT_FALSE(IsLoopbackAddress("192.168.1.5"));
}

class Replay : public ::testing::Test {
 protected:
  // FRONTIERS with 1 frontier at log time 0 s, 2 at 10 s, 3 at 20 s; and an odometry
  // message the viewer does not show.
  void SetUp() override {
    LcmLogWriter log(path_);
    for (int i = 0; i < 3; ++i) {
      const frontier_list_t msg = ToLcm(Frontiers(i * 10'000'000, i + 1));
      log.Write(channels::kFrontiers, 1'000'000'000 + i * 10'000'000, msg);
    }
  }
  const std::string path_ = TestTempPath("replay.lcmlog");
};

TEST_F(Replay, ShowsTheRunAsItWasAtAnyTime) {
  const ViewerReplay replay(path_, /*max_snapshots=*/60);
  EXPECT_DOUBLE_EQ(replay.end_s(), 20.0);
  EXPECT_EQ(replay.events(), 3u);
  for (const auto& [t_s, frontiers] : std::vector<std::pair<double, std::size_t>>{
           {0.0, 1}, {5.0, 1}, {10.0, 2}, {19.9, 2}, {20.0, 3}, {25.0, 3}}) {
    const ViewerModel model = replay.ModelAt(t_s);
    ASSERT_TRUE(model.frontiers().has_value()) << t_s;
    EXPECT_EQ(model.frontiers()->frontiers.size(), frontiers) << "at " << t_s << " s";
  }
  EXPECT_THROW(ViewerReplay("/nonexistent/run.lcmlog"), std::runtime_error);
}

TEST_F(Replay, APageSeeksAndCannotControl) {
  const ViewerReplay replay(path_);
  InProcessHost host;
  ViewerNode node(host.lcm());
  node.SetModel(replay.ModelAt(replay.end_s()));
  ViewerServerOptions options = AnyPort();
  options.allow_control = false;
  ViewerServer server(options, node, ViewerReplayHooks{0.0, replay.end_s(), [&](double t_s) {
                                                         node.SetModel(replay.ModelAt(t_s));
                                                       }});
  Page page(server.port());
  EXPECT_THAT(page.WaitFor("hello"), HasSubstr("\"mode\":\"replay\",\"control\":false"));
  EXPECT_THAT(page.WaitFor("hello"), HasSubstr("\"replay\":{\"start_s\":0.000,\"end_s\":20.000}"));
  server.Push();
  std::size_t next = 0;
  EXPECT_THAT(page.WaitFor("\"frontiers\"", &next), HasSubstr("\"id\":12"));

  page.Send("seek 12.5");
  page.Send("control pause");
  EXPECT_THAT(page.WaitFor("control_result"), HasSubstr("control is off"));
  server.Push();  // the seek was handled before the control's answer
  const std::string after_seek = page.WaitFor("\"reset\":true", &next);
  EXPECT_THAT(after_seek, HasSubstr("\"id\":11"));
  EXPECT_THAT(after_seek, ::testing::Not(HasSubstr("\"id\":12")));
  EXPECT_EQ(server.controls_sent(), 0);
}

}  // namespace
}  // namespace aslam
