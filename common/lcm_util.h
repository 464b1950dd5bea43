#pragma once

// LCM hosting helpers: which URL to use, and subscriptions that never let a
// bad message or a throwing handler escape into LCM.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace aslam {

// Loopback-only default: ttl=0 keeps multicast on this host.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

// The URL from a --lcm-url flag if given, else $LCM_DEFAULT_URL, else kDefaultLcmUrl.
std::string ResolveLcmUrl(const std::string& flag_value);

// Microseconds since the Unix epoch, for messages that carry wall-clock time (procman's,
// EXPLORE_CONTROL); algorithm time is message time, never this.
int64_t WallClockUtime();

// Opens LCM on `url`; throws std::runtime_error naming the URL if it fails
// (e.g. udpm without a multicast route), with a hint how to fix it.
std::unique_ptr<lcm::LCM> OpenLcm(const std::string& url);

// What happened to the messages of one channel.
struct ChannelStats {
  int64_t received = 0;         // decoded and handled
  int64_t decode_failures = 0;  // bytes that are not a valid message of the type
  int64_t rejected = 0;         // decoded, but the handler refused it (invalid content)
  int64_t handler_errors = 0;   // the handler threw; the message was dropped
  double cpu_s = 0.0;           // this thread's CPU seconds decoding and handling
  int64_t dropped() const { return decode_failures + rejected + handler_errors; }
};

// A node's subscriptions. Each handler gets a decoded message and returns
// true if it used it, false to drop it as invalid. Nothing thrown while
// decoding or handling leaves the LCM callback: it is counted instead.
class Subscriptions {
 public:
  explicit Subscriptions(lcm::LCM& lcm) : lcm_(lcm) {}
  ~Subscriptions();
  Subscriptions(const Subscriptions&) = delete;
  Subscriptions& operator=(const Subscriptions&) = delete;

  template <typename MsgT>
  void Add(const std::string& channel, std::function<bool(const MsgT&)> handler);
  // A channel whose publisher moved from LegacyT to MsgT, so logs and tools may carry
  // either: each message goes to the handler of the type whose fingerprint it starts with.
  template <typename MsgT, typename LegacyT>
  void AddWithLegacy(const std::string& channel, std::function<bool(const MsgT&)> handler,
                     std::function<bool(const LegacyT&)> legacy_handler);

  const ChannelStats& stats(const std::string& channel) const;
  // Sum of dropped() over all channels.
  int64_t total_dropped() const;
  // Sum of cpu_s over all channels: what the node's handlers cost.
  double total_cpu_s() const;

 private:
  enum class Outcome { kHandled, kRejected, kDecodeFailed };
  template <typename MsgT>
  static Outcome DecodeAndHandle(const lcm::ReceiveBuffer& rbuf,
                                 const std::function<bool(const MsgT&)>& handler);
  // Whether the message's first 8 bytes are `hash`, big-endian, as LCM encodes it.
  static bool StartsWithFingerprint(const lcm::ReceiveBuffer& rbuf, int64_t hash);
  void AddEntry(const std::string& channel,
                std::function<Outcome(const lcm::ReceiveBuffer&)> decode_and_handle);
  struct Entry {
    std::string channel;
    ChannelStats stats;
    std::function<Outcome(const lcm::ReceiveBuffer&)> decode_and_handle;
    lcm::Subscription* subscription = nullptr;
    void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  };
  lcm::LCM& lcm_;
  std::vector<std::unique_ptr<Entry>> entries_;
};

template <typename MsgT>
void Subscriptions::Add(const std::string& channel, std::function<bool(const MsgT&)> handler) {
  AddEntry(channel, [handler = std::move(handler)](const lcm::ReceiveBuffer& rbuf) {
    return DecodeAndHandle(rbuf, handler);
  });
}

template <typename MsgT, typename LegacyT>
void Subscriptions::AddWithLegacy(const std::string& channel,
                                  std::function<bool(const MsgT&)> handler,
                                  std::function<bool(const LegacyT&)> legacy_handler) {
  AddEntry(channel, [handler = std::move(handler),
                     legacy_handler = std::move(legacy_handler)](const lcm::ReceiveBuffer& rbuf) {
    if (StartsWithFingerprint(rbuf, LegacyT::getHash())) {
      return DecodeAndHandle(rbuf, legacy_handler);
    }
    return DecodeAndHandle(rbuf, handler);
  });
}

template <typename MsgT>
Subscriptions::Outcome Subscriptions::DecodeAndHandle(
    const lcm::ReceiveBuffer& rbuf, const std::function<bool(const MsgT&)>& handler) {
  MsgT message;
  if (message.decode(rbuf.data, 0, rbuf.data_size) != static_cast<int>(rbuf.data_size)) {
    return Outcome::kDecodeFailed;
  }
  return handler(message) ? Outcome::kHandled : Outcome::kRejected;
}

}  // namespace aslam
