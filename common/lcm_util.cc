#include "common/lcm_util.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <utility>

#include "common/cpu_time.h"

namespace aslam {

int64_t WallClockUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string ResolveLcmUrl(const std::string& flag_value) {
  if (!flag_value.empty()) return flag_value;
  const char* env = std::getenv("LCM_DEFAULT_URL");
  if (env != nullptr && env[0] != '\0') return env;
  return kDefaultLcmUrl;
}

std::unique_ptr<lcm::LCM> OpenLcm(const std::string& url) {
  auto lcm = std::make_unique<lcm::LCM>(url);
  if (!lcm->good()) {
    std::string hint;
    if (url.rfind("udpm://", 0) == 0) {
      hint =
          " (udpm needs a multicast route; for loopback only: "
          "sudo ip link set lo multicast on && sudo ip route add 224.0.0.0/4 dev lo)";
    }
    throw std::runtime_error("cannot open LCM on '" + url + "'" + hint);
  }
  return lcm;
}

Subscriptions::~Subscriptions() {
  for (auto& entry : entries_) lcm_.unsubscribe(entry->subscription);
}

void Subscriptions::AddEntry(const std::string& channel,
                             std::function<Outcome(const lcm::ReceiveBuffer&)> decode_and_handle) {
  auto entry = std::make_unique<Entry>();
  entry->channel = channel;
  entry->decode_and_handle = std::move(decode_and_handle);
  entry->subscription = lcm_.subscribe(channel, &Entry::OnMessage, entry.get());
  entries_.push_back(std::move(entry));
}

bool Subscriptions::StartsWithFingerprint(const lcm::ReceiveBuffer& rbuf, int64_t hash) {
  if (rbuf.data_size < 8) return false;
  const auto* bytes = static_cast<const uint8_t*>(rbuf.data);
  uint64_t first = 0;
  for (int i = 0; i < 8; ++i) first = (first << 8) | bytes[i];
  return first == static_cast<uint64_t>(hash);
}

void Subscriptions::Entry::OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  const double cpu_start_s = ThreadCpuSeconds();
  try {
    switch (decode_and_handle(*rbuf)) {
      case Outcome::kHandled: ++stats.received; break;
      case Outcome::kRejected: ++stats.rejected; break;
      case Outcome::kDecodeFailed: ++stats.decode_failures; break;
    }
  } catch (const std::exception& e) {
    if (stats.handler_errors++ == 0) {
      std::fprintf(stderr, "%s: handler error, message dropped: %s\n", channel.c_str(), e.what());
    }
  } catch (...) {
    ++stats.handler_errors;
  }
  stats.cpu_s += ThreadCpuSeconds() - cpu_start_s;
}

const ChannelStats& Subscriptions::stats(const std::string& channel) const {
  static const ChannelStats kNone;
  for (const auto& entry : entries_) {
    if (entry->channel == channel) return entry->stats;
  }
  return kNone;
}

int64_t Subscriptions::total_dropped() const {
  int64_t total = 0;
  for (const auto& entry : entries_) total += entry->stats.dropped();
  return total;
}

double Subscriptions::total_cpu_s() const {
  double total = 0.0;
  for (const auto& entry : entries_) total += entry->stats.cpu_s;
  return total;
}

}  // namespace aslam
