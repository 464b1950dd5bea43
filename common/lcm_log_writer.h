#pragma once

// Writing an lcm-logger file directly (fixtures, benches, tests): each event
// numbered in order, stamped with the time the caller gives (e.g. simulated time).

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace aslam {

class LcmLogWriter {
 public:
  // Throws std::runtime_error naming `path` when it cannot be created.
  explicit LcmLogWriter(const std::string& path);

  // Throws std::runtime_error when the write fails (e.g. the disk is full).
  void WriteBytes(const std::string& channel, int64_t timestamp_us, const void* data, int32_t size);
  template <typename Msg>
  void Write(const std::string& channel, int64_t timestamp_us, const Msg& msg) {
    buffer_.resize(msg.getEncodedSize());
    msg.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
    WriteBytes(channel, timestamp_us, buffer_.data(), static_cast<int32_t>(buffer_.size()));
  }

  int64_t events() const { return events_; }

 private:
  std::string path_;
  lcm::LogFile log_;
  std::vector<uint8_t> buffer_;
  int64_t events_ = 0;
};

}  // namespace aslam
