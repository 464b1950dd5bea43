#include "drivers/io/tcp_stream.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace aslam {
namespace {

std::string ConnectFailure(const std::string& name, int error) {
  switch (error) {
    case ECONNREFUSED:
      return name + ": connection refused (is the sensor on, and is this its address and port?)";
    case ETIMEDOUT:
      return name + ": no answer (check the cable, the address and this computer's subnet)";
    case ENETUNREACH:
    case EHOSTUNREACH:
      return name + ": unreachable (no route: is this computer on the sensor's subnet?)";
    default: return name + ": " + std::strerror(error);
  }
}

}  // namespace

TcpStream::TcpStream(const std::string& host, int port, int timeout_ms)
    : name_(host + ":" + std::to_string(port)) {
  if (port <= 0 || port > 65535) throw DeviceError(name_ + ": port must be 1..65535");
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const int lookup = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found);
  if (lookup != 0) throw DeviceError(name_ + ": unknown host (" + ::gai_strerror(lookup) + ")");
  int last_error = ETIMEDOUT;
  for (addrinfo* a = found; a != nullptr && fd_ < 0; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
      last_error = errno;
      continue;
    }
    int result = ::connect(fd, a->ai_addr, a->ai_addrlen);
    if (result != 0 && errno == EINPROGRESS) {
      pollfd p{fd, POLLOUT, 0};
      const int ready = ::poll(&p, 1, timeout_ms);
      int error = ETIMEDOUT;
      if (ready > 0) {
        socklen_t length = sizeof(error);
        ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length);
      }
      result = error == 0 ? 0 : -1;
      errno = error;
    }
    if (result == 0) {
      fd_ = fd;
    } else {
      last_error = errno;
      ::close(fd);
    }
  }
  ::freeaddrinfo(found);
  if (fd_ < 0) throw DeviceError(ConnectFailure(name_, last_error));
  const int one = 1;
  ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
}

TcpStream::~TcpStream() {
  if (fd_ >= 0) ::close(fd_);
}

std::size_t TcpStream::Read(uint8_t* data, std::size_t size, int timeout_ms) {
  if (size == 0) return 0;
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms < 0 ? 0 : timeout_ms);
  if (ready < 0) {
    if (errno == EINTR) return 0;
    throw DeviceError(name_ + ": " + std::strerror(errno));
  }
  if (ready == 0) return 0;
  const ssize_t n = ::recv(fd_, data, size, 0);
  if (n > 0) return static_cast<std::size_t>(n);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  throw DeviceError(name_ + ": the sensor closed the connection" +
                    (n < 0 ? std::string(": ") + std::strerror(errno) : std::string()));
}

void TcpStream::Write(const uint8_t* data, std::size_t size) {
  std::size_t sent = 0;
  while (sent < size) {
    const ssize_t n = ::send(fd_, data + sent, size - sent, MSG_NOSIGNAL);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) {
      pollfd p{fd_, POLLOUT, 0};
      if (::poll(&p, 1, 1000) <= 0) throw DeviceError(name_ + ": send timed out");
      continue;
    }
    throw DeviceError(name_ +
                      ": send failed: " + (n < 0 ? std::strerror(errno) : "no bytes taken"));
  }
}

void TcpStream::DiscardInput() {
  uint8_t buffer[4096];
  while (::recv(fd_, buffer, sizeof(buffer), MSG_DONTWAIT) > 0) {
  }
}

}  // namespace aslam
