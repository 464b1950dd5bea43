#include "tools/teleop_node.h"

#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <memory>
#include <thread>

#include "common/channels.h"
#include "common/lcm_util.h"
#include "common/robot_config.h"
#include "common/types_lcm.h"
#include "drivers/io/host_clock.h"
#include "tools/teleop.h"

namespace aslam {
namespace {

volatile std::sig_atomic_t g_signal = 0;

void OnSignal(int signal) { g_signal = signal; }

// Without SA_RESTART, so a signal wakes poll() at once.
void CatchStopSignals() {
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  for (int signal : {SIGINT, SIGTERM, SIGHUP}) sigaction(signal, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);  // a closed stdout must not end us before the zero command
}

// The terminal in raw mode (no line buffering, no echo, Ctrl-C as a byte) while it lives.
class RawTerminal {
 public:
  explicit RawTerminal(int fd) : fd_(fd) {
    if (!isatty(fd_) || tcgetattr(fd_, &saved_) != 0) return;
    termios raw = saved_;
    raw.c_lflag &= ~(ICANON | ECHO | ISIG | IEXTEN);
    raw.c_iflag &= ~(IXON | ICRNL);
    raw.c_cc[VMIN] = 1;
    raw.c_cc[VTIME] = 0;
    active_ = tcsetattr(fd_, TCSAFLUSH, &raw) == 0;
  }
  ~RawTerminal() {
    if (active_) tcsetattr(fd_, TCSAFLUSH, &saved_);
  }
  RawTerminal(const RawTerminal&) = delete;
  RawTerminal& operator=(const RawTerminal&) = delete;

 private:
  int fd_;
  termios saved_{};
  bool active_ = false;
};

// The status on one updating line on a terminal; one line per change elsewhere.
class StatusLine {
 public:
  StatusLine() : tty_(isatty(STDOUT_FILENO)) {}
  void Show(const std::string& line) {
    if (line == last_) return;
    last_ = line;
    std::printf(tty_ ? "\r%s\x1b[K" : "%s\n", line.c_str());
    std::fflush(stdout);
  }
  void Finish() {
    if (tty_ && !last_.empty()) std::printf("\n");
  }

 private:
  bool tty_;
  std::string last_;
};

double NowS() { return static_cast<double>(HostClockUtime()) * 1e-6; }

void Publish(lcm::LCM& lcm, double linear_mps, double angular_radps) {
  VelocityCommand command;
  command.utime = HostClockUtime();  // the base times commands by arrival; this is for logs
  command.linear_mps = linear_mps;
  command.angular_radps = angular_radps;
  const velocity_command_t msg = ToLcm(command);
  lcm.publish(channels::kCmdVel, &msg);
}

// Reads what stdin has; false at its end (or on an error other than an interruption).
bool ReadKeys(KeyDecoder* decoder, Teleop* teleop) {
  unsigned char bytes[64];
  const ssize_t n = read(STDIN_FILENO, bytes, sizeof(bytes));
  if (n < 0) return errno == EINTR || errno == EAGAIN;
  for (ssize_t i = 0; i < n; ++i) {
    if (const auto key = decoder->Feed(bytes[i])) teleop->OnKey(*key, NowS());
  }
  return n > 0;
}

}  // namespace

int RunTeleopProcess(const TeleopProcessOptions& options) {
  if (!(options.rate_hz > 0 && options.rate_hz <= 100)) {
    std::fprintf(stderr, "aslam-teleop: --rate %g: expected 0 < Hz <= 100\n", options.rate_hz);
    return 2;
  }
  if (!(options.deadman_s > 0 && options.deadman_s <= 10)) {
    std::fprintf(stderr, "aslam-teleop: --deadman-s %g: expected 0 < s <= 10\n", options.deadman_s);
    return 2;
  }
  if (!options.keys_from_pipe && !isatty(STDIN_FILENO)) {
    std::fprintf(stderr,
                 "aslam-teleop: stdin is not a terminal, so keys cannot be read as typed: run "
                 "it in a terminal (over ssh: ssh -t), or give --stdin to read keys from a pipe "
                 "(tests)\n");
    return 2;
  }
  TeleopOptions teleop_options;
  std::string url;
  std::unique_ptr<lcm::LCM> lcm;
  try {
    teleop_options = TeleopOptionsFromRobot(LoadRobotOptionsFromFile(options.config_file));
    teleop_options.deadman_s = options.deadman_s;
    url = ResolveLcmUrl(options.lcm_url);
    lcm = OpenLcm(url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-teleop: %s\n", e.what());
    return 1;
  }
  Teleop teleop(teleop_options);
  KeyDecoder decoder;
  CatchStopSignals();
  std::printf("aslam-teleop: %s on %s at %g Hz\n%s", channels::kCmdVel, url.c_str(),
              options.rate_hz, TeleopKeyMap(teleop_options).c_str());
  std::fflush(stdout);

  const char* end = "quit";
  {
    const RawTerminal terminal(STDIN_FILENO);
    StatusLine status;
    const double period_s = 1.0 / options.rate_hz;
    double next_publish_s = 0.0;
    double sent_linear = 0.0;
    double sent_angular = 0.0;
    while (!teleop.quit()) {
      double now_s = NowS();
      const double wake_s = std::min(teleop.deadman_deadline_s(),
                                     teleop.ShouldPublish(now_s) ? next_publish_s : now_s + 1.0);
      const int timeout_ms =
          static_cast<int>(std::clamp(std::ceil((wake_s - now_s) * 1000.0), 0.0, 1000.0));
      pollfd input{STDIN_FILENO, POLLIN, 0};
      if (poll(&input, 1, timeout_ms) > 0 && !ReadKeys(&decoder, &teleop)) {
        end = "end of input";
        break;
      }
      if (g_signal != 0) {
        end = g_signal == SIGINT ? "SIGINT" : g_signal == SIGTERM ? "SIGTERM" : "SIGHUP";
        break;
      }
      now_s = NowS();
      teleop.Update(now_s);
      const bool changed =
          teleop.linear_mps() != sent_linear || teleop.angular_radps() != sent_angular;
      if (teleop.ShouldPublish(now_s) && (changed || now_s >= next_publish_s)) {
        Publish(*lcm, teleop.linear_mps(), teleop.angular_radps());
        sent_linear = teleop.linear_mps();
        sent_angular = teleop.angular_radps();
        next_publish_s = now_s + period_s;
      }
      status.Show(teleop.StatusLine());
    }
    // Three zeros, so that one lost datagram (Wi-Fi) cannot leave the robot driving until
    // the base's own command timeout.
    for (int i = 0; i < 3; ++i) {
      Publish(*lcm, 0.0, 0.0);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    status.Finish();
  }  // the terminal is restored here
  std::printf("aslam-teleop: %s; sent a zero command\n", end);
  return 0;
}

}  // namespace aslam
