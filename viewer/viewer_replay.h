#pragma once

// `aslam view RUN_FOLDER` and `aslam-viewer --log FILE`: a finished run's lcm log, shown at
// any time a page's slider asks for. The log is read once; the model is kept as it was every
// snapshot period, so a seek replays at most one period of messages.

#include <cstdint>
#include <string>
#include <vector>

#include "viewer/viewer_model.h"

namespace aslam {

class ViewerReplay {
 public:
  // Reads the whole log; throws std::runtime_error naming the file when it cannot be read
  // or holds no event.
  explicit ViewerReplay(const std::string& log_path, int max_snapshots = 60);

  // Log time of the last event, seconds after the first.
  double end_s() const { return end_s_; }
  // The model as it was at t_s (log time after the first event), every message up to it shown.
  ViewerModel ModelAt(double t_s) const;
  std::size_t events() const { return events_.size(); }

 private:
  struct Event {
    double t_s;
    std::string channel;
    std::string data;
  };
  struct Snapshot {
    std::size_t next_event;  // the first event not in the model
    ViewerModel model;
  };
  // Feeds events [from, to) into `model`.
  void Feed(ViewerModel* model, std::size_t from, std::size_t to) const;

  std::vector<Event> events_;
  std::vector<Snapshot> snapshots_;
  double end_s_ = 0.0;
};

}  // namespace aslam
