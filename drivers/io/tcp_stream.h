#pragma once

// A TCP connection to a networked sensor (e.g. a Hokuyo UST at 192.168.0.10:10940).

#include <string>

#include "drivers/io/byte_stream.h"

namespace aslam {

class TcpStream final : public ByteStream {
 public:
  // Connects to `host` (an IPv4/IPv6 address or name) at `port` within `timeout_ms`;
  // throws DeviceError naming host:port and what went wrong (refused, timed out, ...).
  TcpStream(const std::string& host, int port, int timeout_ms);
  ~TcpStream() override;
  TcpStream(const TcpStream&) = delete;
  TcpStream& operator=(const TcpStream&) = delete;

  std::size_t Read(uint8_t* data, std::size_t size, int timeout_ms) override;
  void Write(const uint8_t* data, std::size_t size) override;
  void DiscardInput() override;
  const std::string& name() const override { return name_; }

 private:
  std::string name_;
  int fd_ = -1;
};

}  // namespace aslam
