#include "drivers/io/serial_port.h"

// termios2 (not <termios.h>, whose struct clashes with it) sets arbitrary baud rates.
#include <asm/termbits.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace aslam {
namespace {

std::string OpenFailure(const std::string& path, int error) {
  const std::string head = "serial port " + path + ": ";
  switch (error) {
    case ENOENT:
      return head + "no such device (is it plugged in? `ls -l /dev/serial/by-id/` lists ports)";
    case EACCES:
    case EPERM:
      return head +
             "permission denied (add the user to the 'dialout' group and log in again, or "
             "install the udev rule from the README)";
    case EBUSY: return head + "in use by another process";
    case ENXIO:
    case ENODEV: return head + "the device is not there (unplugged?)";
    default: return head + std::strerror(error);
  }
}

}  // namespace

SerialPort::SerialPort(const std::string& path, int baud) : path_(path), baud_(baud) {
  if (baud <= 0) throw DeviceError("serial port " + path + ": baud rate must be > 0");
  fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw DeviceError(OpenFailure(path, errno));
  struct termios2 tio {};
  if (::ioctl(fd_, TCGETS2, &tio) != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    throw DeviceError("serial port " + path + ": not a serial port (" + std::strerror(error) + ")");
  }
  // Raw 8N1, no flow control, no echo, no line discipline, receiver on, modem lines ignored.
  tio.c_iflag &=
      ~(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR | ICRNL | IXON | IXOFF | IXANY | INPCK);
  tio.c_oflag &= ~OPOST;
  tio.c_lflag &= ~(ECHO | ECHONL | ICANON | ISIG | IEXTEN);
  tio.c_cflag &= ~(CSIZE | PARENB | CSTOPB | CRTSCTS | CBAUD);
  tio.c_cflag |= CS8 | CREAD | CLOCAL | BOTHER;
  tio.c_ispeed = static_cast<speed_t>(baud);
  tio.c_ospeed = static_cast<speed_t>(baud);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  if (::ioctl(fd_, TCSETS2, &tio) != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    throw DeviceError("serial port " + path + ": cannot set " + std::to_string(baud) +
                      " baud 8N1 (" + std::strerror(error) + ")");
  }
  // A second driver on the same port would steal bytes: refuse it.
  ::ioctl(fd_, TIOCEXCL);
  DiscardInput();
}

SerialPort::~SerialPort() {
  if (fd_ < 0) return;
  // TIOCEXCL stays on the tty while any other fd holds it (an emulator's pseudo-terminal, a
  // serial console): released, so this driver can open the port again after a reconnect.
  ::ioctl(fd_, TIOCNXCL);
  ::close(fd_);
}

std::size_t SerialPort::Read(uint8_t* data, std::size_t size, int timeout_ms) {
  if (size == 0) return 0;
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms < 0 ? 0 : timeout_ms);
  if (ready < 0) {
    if (errno == EINTR) return 0;
    throw DeviceError("serial port " + path_ + ": " + std::strerror(errno));
  }
  if (ready == 0) return 0;
  if (p.revents & (POLLERR | POLLNVAL)) {
    throw DeviceError("serial port " + path_ + ": the device is gone (unplugged?)");
  }
  const ssize_t n = ::read(fd_, data, size);
  if (n > 0) return static_cast<std::size_t>(n);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  // Readable but no bytes (EOF) or EIO: the other end went away.
  throw DeviceError("serial port " + path_ + ": the device is gone (unplugged?)" +
                    (n < 0 ? std::string(": ") + std::strerror(errno) : std::string()));
}

void SerialPort::Write(const uint8_t* data, std::size_t size) {
  std::size_t sent = 0;
  while (sent < size) {
    const ssize_t n = ::write(fd_, data + sent, size - sent);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) {
      pollfd p{fd_, POLLOUT, 0};
      if (::poll(&p, 1, 1000) <= 0) {
        throw DeviceError("serial port " + path_ + ": write timed out");
      }
      continue;
    }
    throw DeviceError("serial port " + path_ +
                      ": write failed: " + (n < 0 ? std::strerror(errno) : "no bytes taken"));
  }
}

void SerialPort::DiscardInput() { ::ioctl(fd_, TCFLSH, TCIFLUSH); }

bool SerialPort::SetDtr(bool asserted) {
  const int line = TIOCM_DTR;
  return ::ioctl(fd_, asserted ? TIOCMBIS : TIOCMBIC, &line) == 0;
}

}  // namespace aslam
