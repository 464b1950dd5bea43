#include "drivers/io/pseudo_terminal.h"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace aslam {

PseudoTerminal::PseudoTerminal() {
  char name[256] = {};
  termios raw{};
  cfmakeraw(&raw);
  if (::openpty(&master_fd_, &slave_fd_, name, &raw, nullptr) != 0) {
    throw std::runtime_error(std::string("openpty: ") + std::strerror(errno));
  }
  ::fcntl(master_fd_, F_SETFD, FD_CLOEXEC);
  ::fcntl(slave_fd_, F_SETFD, FD_CLOEXEC);
  ::fcntl(master_fd_, F_SETFL, ::fcntl(master_fd_, F_GETFL) | O_NONBLOCK);
  slave_path_ = name;
}

PseudoTerminal::~PseudoTerminal() { Close(); }

std::vector<uint8_t> PseudoTerminal::Read(int timeout_ms) {
  std::vector<uint8_t> bytes;
  if (master_fd_ < 0) return bytes;
  pollfd p{master_fd_, POLLIN, 0};
  if (::poll(&p, 1, timeout_ms) <= 0 || !(p.revents & POLLIN)) return bytes;
  uint8_t buffer[4096];
  for (;;) {
    const ssize_t n = ::read(master_fd_, buffer, sizeof(buffer));
    if (n <= 0) break;
    bytes.insert(bytes.end(), buffer, buffer + n);
  }
  return bytes;
}

void PseudoTerminal::Write(const std::vector<uint8_t>& bytes) {
  std::size_t sent = 0;
  while (master_fd_ >= 0 && sent < bytes.size()) {
    const ssize_t n = ::write(master_fd_, bytes.data() + sent, bytes.size() - sent);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
    } else if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd p{master_fd_, POLLOUT, 0};
      ::poll(&p, 1, 100);
    } else {
      break;
    }
  }
}

void PseudoTerminal::Close() {
  if (slave_fd_ >= 0) ::close(slave_fd_);
  if (master_fd_ >= 0) ::close(master_fd_);
  slave_fd_ = master_fd_ = -1;
}

DeviceLink::DeviceLink(const std::string& path, const std::string& name) : path_(path) {
  if (!path_.empty()) return;
  std::string dir = "/tmp/" + name + "_emulator_XXXXXX";
  if (!::mkdtemp(dir.data()))
    throw std::runtime_error(std::string("mkdtemp: ") + std::strerror(errno));
  dir_ = dir;
  path_ = dir_ + "/" + name;
}

DeviceLink::~DeviceLink() {
  Remove();
  if (!dir_.empty()) ::rmdir(dir_.c_str());
}

void DeviceLink::PointAt(const std::string& target) {
  const std::string temporary = path_ + ".new";
  ::unlink(temporary.c_str());
  if (::symlink(target.c_str(), temporary.c_str()) != 0 ||
      ::rename(temporary.c_str(), path_.c_str()) != 0) {
    throw std::runtime_error("cannot point " + path_ + " at " + target);
  }
}

void DeviceLink::Remove() { ::unlink(path_.c_str()); }

}  // namespace aslam
