#pragma once

// aslam-teleop's logic: keyboard bytes in, a velocity command out. No LCM, no terminal,
// no clock: the caller passes the time, so every rule is testable.
//
// The robot moves only while a motion key is held: the terminal's auto-repeat resends
// it many times a second, and with no motion key for `deadman_s` the command returns to
// zero (the dead man). Speeds go in steps of a tenth of the `robot:` section's limits,
// never above them.
//
//   u i o    forward-left   forward  forward-right
//   j k l    turn left      STOP     turn right
//   m , .    back-left      back     back-right      (arrow keys: i , j l)
//   space or k: stop now     + / -: both speeds a step up / down
//   w / x: linear speed up / down     e / c: angular speed up / down
//   q, Q or Ctrl-C: stop and quit

#include <limits>
#include <optional>
#include <string>

#include "common/robot_config.h"

namespace aslam {

// Key codes: a byte 0..255 as typed, or one of these for the arrow keys.
inline constexpr int kKeyUp = 0x100;
inline constexpr int kKeyDown = 0x101;
inline constexpr int kKeyRight = 0x102;
inline constexpr int kKeyLeft = 0x103;
inline constexpr int kKeyCtrlC = 0x03;

// Turns terminal bytes into key codes: plain bytes as they are, the escape sequences of
// the arrow keys (ESC [ A, ESC O A, and with modifiers ESC [ 1 ; 5 A) into kKey*. Other
// escape sequences (function keys, ...) are swallowed whole.
class KeyDecoder {
 public:
  std::optional<int> Feed(unsigned char byte);

 private:
  enum class State { kPlain, kEscape, kSequence };
  State state_ = State::kPlain;
};

struct TeleopOptions {
  double max_linear_mps = 0.5;  // the robot: section's limits
  double max_angular_radps = 1.8;
  int speed_levels = 10;         // level n of speed_levels drives at n / speed_levels of the limit
  int initial_linear_level = 4;  // 0.2 m/s of 0.5
  int initial_angular_level = 4;
  // 0.6 s outlasts the usual pause before auto-repeat begins (GNOME, KDE: 0.5 s; the Linux
  // console: 0.25 s), so a held key never lapses; a bare X server waits 0.66 s: raise it there.
  double deadman_s = 0.6;
  // After a stop, zeros go out this long (a lost datagram cannot leave the robot moving);
  // then aslam-teleop is silent until the next key, so an idle one never fights aslam-nav.
  double zero_hold_s = 1.0;
};

// The limits of `robot`, the rest defaults.
TeleopOptions TeleopOptionsFromRobot(const RobotOptions& robot);
// Throws std::invalid_argument naming the first bad value.
void ValidateTeleopOptions(const TeleopOptions& options);

enum class TeleopEvent { kIgnored, kMotion, kStop, kSpeed, kQuit };

class Teleop {
 public:
  explicit Teleop(const TeleopOptions& options);  // validates

  // One key at `now_s` (seconds, any monotonic origin).
  TeleopEvent OnKey(int key, double now_s);
  // Applies the dead man: a motion whose last key is more than deadman_s old stops.
  void Update(double now_s);

  // The command as of the last OnKey/Update.
  double linear_mps() const { return linear_dir_ * linear_speed_mps(); }
  double angular_radps() const { return angular_dir_ * angular_speed_radps(); }
  bool moving() const { return linear_dir_ != 0 || angular_dir_ != 0; }
  // Whether commands should go out at `now_s`: while moving, and zero_hold_s after a stop.
  bool ShouldPublish(double now_s) const;
  // When the dead man stops the current motion; +inf when not moving.
  double deadman_deadline_s() const;
  bool quit() const { return quit_; }

  // What a motion key drives at.
  double linear_speed_mps() const;
  double angular_speed_radps() const;
  int linear_level() const { return linear_level_; }
  int angular_level() const { return angular_level_; }

  // The command and speeds on one line, for the terminal.
  std::string StatusLine() const;

 private:
  void Stop(double now_s);

  TeleopOptions options_;
  int linear_dir_ = 0;  // -1, 0, +1
  int angular_dir_ = 0;
  int linear_level_;
  int angular_level_;
  double last_motion_s_ = 0.0;
  double stopped_s_ = -std::numeric_limits<double>::infinity();  // last stop; -inf: none yet
  bool quit_ = false;
};

// The key map as printed at start, with the limits and the dead-man time.
std::string TeleopKeyMap(const TeleopOptions& options);

}  // namespace aslam
