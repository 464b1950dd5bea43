#pragma once

// The clock of one message stream (a sensor's stamps): stamps must move forward by at
// most a gap. A stamp out of line (not later, or a jump) is held back, so one bad stamp
// costs only its message; `resync_messages` out-of-line stamps in a row that follow one
// another restart the clock from them, so a real clock step is followed. Streams merged
// from several channels arrive slightly out of order: a `late_tolerance_us` accepts stamps
// that far behind the clock without moving it.

#include <cstdint>

namespace aslam {

// Defaults for sensor streams: a gap longer than any lidar's or base's period, and enough
// agreeing messages that one or two bad stamps never restart the clock.
constexpr double kDefaultMaxTimeGapS = 1.0;
constexpr int kDefaultResyncMessages = 3;

class StreamClock {
 public:
  enum class Verdict {
    kInLine,     // accepted: follows the clock
    kLate,       // accepted: behind the clock by at most the late tolerance (clock unchanged)
    kResynced,   // accepted: the last of the out-of-line stamps that restart the clock
    kBackwards,  // held back: not after the clock
    kJump,       // held back: later than the clock by more than the gap
  };

  StreamClock(int64_t max_gap_us, int resync_messages, int64_t late_tolerance_us = 0)
      : max_gap_us_(max_gap_us),
        resync_messages_(resync_messages),
        late_tolerance_us_(late_tolerance_us) {}

  Verdict Offer(int64_t utime) {
    if (!started_ || (utime > now_utime_ && utime - now_utime_ <= max_gap_us_)) {
      return Accept(utime, Verdict::kInLine);
    }
    if (late_tolerance_us_ > 0 && utime <= now_utime_ && now_utime_ - utime <= late_tolerance_us_) {
      held_back_ = 0;
      return Verdict::kLate;
    }
    if (held_back_ == 0 || !Follows(last_held_utime_, utime)) held_back_ = 0;
    ++held_back_;
    last_held_utime_ = utime;
    if (held_back_ >= resync_messages_) return Accept(utime, Verdict::kResynced);
    return utime <= now_utime_ ? Verdict::kBackwards : Verdict::kJump;
  }
  static bool Accepted(Verdict verdict) {
    return verdict == Verdict::kInLine || verdict == Verdict::kLate ||
           verdict == Verdict::kResynced;
  }

  bool started() const { return started_; }
  int64_t now_utime() const { return now_utime_; }  // the latest accepted stamp
  int64_t resyncs() const { return resyncs_; }

 private:
  // Whether held-back stamps agree: in order (up to the late tolerance), within the gap.
  bool Follows(int64_t from, int64_t to) const {
    return to > from - late_tolerance_us_ && to - from <= max_gap_us_;
  }
  Verdict Accept(int64_t utime, Verdict verdict) {
    if (verdict == Verdict::kResynced) ++resyncs_;
    started_ = true;
    now_utime_ = utime;
    held_back_ = 0;
    return verdict;
  }

  int64_t max_gap_us_;
  int resync_messages_;
  int64_t late_tolerance_us_;
  bool started_ = false;
  int64_t now_utime_ = 0;
  int held_back_ = 0;
  int64_t last_held_utime_ = 0;
  int64_t resyncs_ = 0;
};

}  // namespace aslam
