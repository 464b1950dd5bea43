#include "viewer/viewer_replay.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include <lcm/lcm-cpp.hpp>

#include "common/inproc_host.h"
#include "viewer/viewer_lcm.h"

namespace aslam {

ViewerReplay::ViewerReplay(const std::string& log_path, int max_snapshots) {
  lcm::LogFile log(log_path, "r");
  if (!log.good()) throw std::runtime_error(log_path + ": cannot read this lcm log");
  std::optional<int64_t> first_timestamp;
  const std::vector<std::string>& shown = ViewerChannels();
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    if (!first_timestamp) first_timestamp = event->timestamp;
    // Only what the viewer shows is kept: a run's log is mostly odometry and truth.
    if (std::find(shown.begin(), shown.end(), event->channel) == shown.end()) continue;
    // Log timestamps can step back a little (several writers); the slider wants them in order.
    const double t_s = std::max(end_s_, (event->timestamp - *first_timestamp) * 1e-6);
    events_.push_back(
        {t_s, event->channel, std::string(static_cast<const char*>(event->data), event->datalen)});
    end_s_ = t_s;
  }
  if (events_.empty()) {
    throw std::runtime_error(log_path +
                             ": no message on a channel the viewer shows (SLAM_MAP, "
                             "SLAM_POSE, FRONTIERS, ...)");
  }
  const double period_s = std::max(10.0, end_s_ / std::max(1, max_snapshots));
  ViewerModel model;
  std::size_t next = 0;
  for (double t = 0.0; next < events_.size(); t += period_s) {
    std::size_t until = next;
    while (until < events_.size() && events_[until].t_s <= t) ++until;
    Feed(&model, next, until);
    next = until;
    snapshots_.push_back({next, model});
  }
}

void ViewerReplay::Feed(ViewerModel* model, std::size_t from, std::size_t to) const {
  if (from >= to) return;
  // The live path's decoding and checks, fed from the log through an in-process bus.
  InProcessHost host;
  ViewerNode node(host.lcm());
  node.SetModel(std::move(*model));
  for (std::size_t i = from; i < to; ++i) {
    const Event& e = events_[i];
    host.lcm().publish(e.channel, e.data.data(), static_cast<unsigned int>(e.data.size()));
    host.DispatchPending();
  }
  *model = node.model();
}

ViewerModel ViewerReplay::ModelAt(double t_s) const {
  // The newest snapshot that holds no event after t_s.
  auto it = std::upper_bound(snapshots_.begin(), snapshots_.end(), t_s,
                             [this](double t, const Snapshot& s) {
                               return s.next_event > 0 && events_[s.next_event - 1].t_s > t;
                             });
  ViewerModel model;
  std::size_t from = 0;
  if (it != snapshots_.begin()) {
    --it;
    model = it->model;
    from = it->next_event;
  }
  std::size_t to = from;
  while (to < events_.size() && events_[to].t_s <= t_s) ++to;
  Feed(&model, from, to);
  return model;
}

}  // namespace aslam
