#pragma once

// A byte stream to a device (serial port or TCP socket), as the lidar and base
// drivers see it: reads that wait a bounded time, writes that send everything,
// and one exception type whose message names the device and what went wrong.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace aslam {

// The device is missing, refused, gone (unplugged) or failed; what() names it.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ByteStream {
 public:
  virtual ~ByteStream() = default;
  // Up to `size` bytes: waits at most `timeout_ms` for the first, then takes what is there.
  // Returns 0 on a timeout; throws DeviceError when the device is gone or fails.
  virtual std::size_t Read(uint8_t* data, std::size_t size, int timeout_ms) = 0;
  // All `size` bytes, or throws DeviceError.
  virtual void Write(const uint8_t* data, std::size_t size) = 0;
  // Drops whatever has arrived and not been read.
  virtual void DiscardInput() = 0;
  // The device as a user named it: "/dev/ttyUSB0", "192.168.0.10:10940".
  virtual const std::string& name() const = 0;
};

}  // namespace aslam
