#include "tools/teleop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace aslam {
namespace {

constexpr unsigned char kEscape = 0x1b;

struct Motion {
  int linear;
  int angular;
};

// The motion a key asks for, if it is a motion key. Backing up along an arc turns like a
// car: m (back-left) ends up behind and to the left.
std::optional<Motion> MotionOf(int key) {
  switch (key) {
    case 'i':
    case kKeyUp: return Motion{1, 0};
    case ',':
    case kKeyDown: return Motion{-1, 0};
    case 'j':
    case kKeyLeft: return Motion{0, 1};
    case 'l':
    case kKeyRight: return Motion{0, -1};
    case 'u': return Motion{1, 1};
    case 'o': return Motion{1, -1};
    case 'm': return Motion{-1, -1};
    case '.': return Motion{-1, 1};
    default: return std::nullopt;
  }
}

}  // namespace

std::optional<int> KeyDecoder::Feed(unsigned char byte) {
  switch (state_) {
    case State::kPlain:
      if (byte == kEscape) {
        state_ = State::kEscape;
        return std::nullopt;
      }
      return byte;
    case State::kEscape:
      if (byte == '[' || byte == 'O') {
        state_ = State::kSequence;
        return std::nullopt;
      }
      // A lone Escape key: dropped; this byte is a key of its own.
      state_ = State::kPlain;
      return Feed(byte);
    case State::kSequence:
      // Parameter and intermediate bytes (0x20-0x3f) until the final byte (0x40-0x7e).
      if (byte >= 0x20 && byte <= 0x3f) return std::nullopt;
      state_ = State::kPlain;
      switch (byte) {
        case 'A': return kKeyUp;
        case 'B': return kKeyDown;
        case 'C': return kKeyRight;
        case 'D': return kKeyLeft;
        default: return std::nullopt;
      }
  }
  return std::nullopt;
}

TeleopOptions TeleopOptionsFromRobot(const RobotOptions& robot) {
  TeleopOptions options;
  options.max_linear_mps = robot.max_linear_mps;
  options.max_angular_radps = robot.max_angular_radps;
  return options;
}

void ValidateTeleopOptions(const TeleopOptions& o) {
  auto require = [](bool ok, const char* what, double value) {
    if (!ok) {
      char text[160];
      std::snprintf(text, sizeof(text), "%s = %g is out of range", what, value);
      throw std::invalid_argument(text);
    }
  };
  require(std::isfinite(o.max_linear_mps) && o.max_linear_mps > 0, "max_linear_mps",
          o.max_linear_mps);
  require(std::isfinite(o.max_angular_radps) && o.max_angular_radps > 0, "max_angular_radps",
          o.max_angular_radps);
  require(o.speed_levels >= 1 && o.speed_levels <= 100, "speed_levels", o.speed_levels);
  require(o.initial_linear_level >= 1 && o.initial_linear_level <= o.speed_levels,
          "initial_linear_level", o.initial_linear_level);
  require(o.initial_angular_level >= 1 && o.initial_angular_level <= o.speed_levels,
          "initial_angular_level", o.initial_angular_level);
  // Above 10 s a released key would leave the robot driving blind for too long.
  require(std::isfinite(o.deadman_s) && o.deadman_s > 0 && o.deadman_s <= 10, "deadman_s (s)",
          o.deadman_s);
  require(std::isfinite(o.zero_hold_s) && o.zero_hold_s >= 0 && o.zero_hold_s <= 60,
          "zero_hold_s (s)", o.zero_hold_s);
}

Teleop::Teleop(const TeleopOptions& options)
    : options_(options),
      linear_level_(options.initial_linear_level),
      angular_level_(options.initial_angular_level) {
  ValidateTeleopOptions(options_);
}

void Teleop::Stop(double now_s) {
  linear_dir_ = 0;
  angular_dir_ = 0;
  stopped_s_ = now_s;
}

void Teleop::Update(double now_s) {
  if (moving() && now_s - last_motion_s_ > options_.deadman_s) Stop(now_s);
}

TeleopEvent Teleop::OnKey(int key, double now_s) {
  Update(now_s);
  if (quit_) return TeleopEvent::kIgnored;
  if (key >= 'A' && key <= 'Z') key += 'a' - 'A';
  if (const auto motion = MotionOf(key)) {
    linear_dir_ = motion->linear;
    angular_dir_ = motion->angular;
    last_motion_s_ = now_s;
    return TeleopEvent::kMotion;
  }
  const auto step = [this](int* level, int delta) {
    *level = std::clamp(*level + delta, 1, options_.speed_levels);
    return TeleopEvent::kSpeed;
  };
  switch (key) {
    case ' ':
    case 'k': Stop(now_s); return TeleopEvent::kStop;
    case 'q':
    case kKeyCtrlC:
      Stop(now_s);
      quit_ = true;
      return TeleopEvent::kQuit;
    case '+':
    case '=': step(&linear_level_, 1); return step(&angular_level_, 1);
    case '-':
    case '_': step(&linear_level_, -1); return step(&angular_level_, -1);
    case 'w': return step(&linear_level_, 1);
    case 'x': return step(&linear_level_, -1);
    case 'e': return step(&angular_level_, 1);
    case 'c': return step(&angular_level_, -1);
    default: return TeleopEvent::kIgnored;
  }
}

bool Teleop::ShouldPublish(double now_s) const {
  return moving() || now_s - stopped_s_ <= options_.zero_hold_s;
}

double Teleop::deadman_deadline_s() const {
  return moving() ? last_motion_s_ + options_.deadman_s : std::numeric_limits<double>::infinity();
}

double Teleop::linear_speed_mps() const {
  // The top level is the limit itself, not a rounded product.
  if (linear_level_ == options_.speed_levels) return options_.max_linear_mps;
  return options_.max_linear_mps * linear_level_ / options_.speed_levels;
}

double Teleop::angular_speed_radps() const {
  if (angular_level_ == options_.speed_levels) return options_.max_angular_radps;
  return options_.max_angular_radps * angular_level_ / options_.speed_levels;
}

std::string Teleop::StatusLine() const {
  char line[200];
  std::snprintf(line, sizeof(line),
                "command %+.2f m/s %+.2f rad/s | speeds %.2f m/s (%d/%d) %.2f rad/s (%d/%d) | %s",
                linear_mps(), angular_radps(), linear_speed_mps(), linear_level_,
                options_.speed_levels, angular_speed_radps(), angular_level_, options_.speed_levels,
                quit_      ? "quit"
                : moving() ? "driving"
                           : "stopped");
  return line;
}

std::string TeleopKeyMap(const TeleopOptions& options) {
  char text[1200];
  std::snprintf(text, sizeof(text),
                "Hold a key to drive; let go and the robot stops within %.2g s.\n"
                "   u  i  o     forward-left  forward  forward-right\n"
                "   j  k  l     turn left     STOP     turn right\n"
                "   m  ,  .     back-left     back     back-right\n"
                "   arrow keys: forward, back, turn left, turn right\n"
                "   space or k: stop now       + / -: both speeds a step up / down\n"
                "   w / x: linear speed up / down   e / c: angular speed up / down\n"
                "   q or Ctrl-C: stop and quit\n"
                "Limits (robot: section): %.2f m/s, %.2f rad/s, in %d steps.\n",
                options.deadman_s, options.max_linear_mps, options.max_angular_radps,
                options.speed_levels);
  return text;
}

}  // namespace aslam
