#pragma once

// A serial port in raw 8N1 mode at any baud rate (termios2, so 256000 and
// 1000000 work as well as the POSIX rates), without flow control. Opening
// explains the usual failures: no such port, permission denied, not a tty,
// already in use.

#include <string>

#include "drivers/io/byte_stream.h"

namespace aslam {

class SerialPort final : public ByteStream {
 public:
  // Opens `path` at `baud`; throws DeviceError naming the port and what to check.
  SerialPort(const std::string& path, int baud);
  ~SerialPort() override;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  std::size_t Read(uint8_t* data, std::size_t size, int timeout_ms) override;
  void Write(const uint8_t* data, std::size_t size) override;
  void DiscardInput() override;
  const std::string& name() const override { return path_; }

  // Sets the DTR line (the RPLidar A1/A2 motor enable is wired to it, active low).
  // Returns false where the port has no modem lines (a pseudo-terminal).
  bool SetDtr(bool asserted);
  int baud() const { return baud_; }

 private:
  std::string path_;
  int baud_ = 0;
  int fd_ = -1;
};

}  // namespace aslam
