#pragma once

// Test support: a pseudo-terminal pair standing in for a USB serial device.
// The emulator holds the master end; the driver opens slave_path() as its
// port. Close() is an unplug: the driver's reads fail as they would on a
// pulled USB adapter.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace aslam {

class PseudoTerminal {
 public:
  // Throws std::runtime_error if the system has no free pseudo-terminal.
  PseudoTerminal();
  ~PseudoTerminal();
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;

  const std::string& slave_path() const { return slave_path_; }
  int master_fd() const { return master_fd_; }
  // Bytes the driver wrote, waiting at most timeout_ms for the first (empty on timeout).
  std::vector<uint8_t> Read(int timeout_ms);
  // Bytes for the driver to read.
  void Write(const std::vector<uint8_t>& bytes);
  // Unplug: closes both ends; the driver's port reads fail from now on.
  void Close();
  bool open() const { return master_fd_ >= 0; }

 private:
  int master_fd_ = -1;
  int slave_fd_ = -1;  // held open so the master never sees a hang-up before the driver opens
  std::string slave_path_;
};

// A stable path to a pseudo-terminal, as udev's /dev/kobuki or /dev/serial/by-id links are:
// re-pointed at once on a replug (a new link renamed over the old, so it never dangles
// half-made), removed on an unplug and with this object.
class DeviceLink {
 public:
  // `path` "" = NAME in a temporary folder of its own, removed with it.
  DeviceLink(const std::string& path, const std::string& name);
  ~DeviceLink();
  DeviceLink(const DeviceLink&) = delete;
  DeviceLink& operator=(const DeviceLink&) = delete;

  const std::string& path() const { return path_; }
  // Throws std::runtime_error naming the link if it cannot be made.
  void PointAt(const std::string& target);
  void Remove();

 private:
  std::string dir_;  // the temporary folder, when this made one
  std::string path_;
};

}  // namespace aslam
