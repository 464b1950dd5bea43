#include <fcntl.h>
#include <netinet/in.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/io/pseudo_terminal.h"
#include "drivers/io/serial_port.h"
#include "drivers/io/tcp_stream.h"

namespace aslam {
namespace {

std::vector<uint8_t> ReadAll(ByteStream& stream, std::size_t count) {
  std::vector<uint8_t> bytes(count);
  std::size_t got = 0;
  for (int tries = 0; got < count && tries < 50; ++tries) {
    got += stream.Read(bytes.data() + got, count - got, 100);
  }
  bytes.resize(got);
  return bytes;
}

std::string ErrorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const DeviceError& e) {
    return e.what();
  }
  return "";
}

TEST(SerialPort, CarriesBytesBothWaysUnchangedAtAnyBaud) {
  PseudoTerminal device;
  SerialPort port(device.slave_path(), 256000);  // not a POSIX rate: termios2
  // Raw mode: CR, LF, XON/XOFF and 0xFF pass untouched.
  const std::vector<uint8_t> from_device = {0xA5, 0x5A, 0x0D, 0x0A, 0x11, 0x13, 0xFF, 0x00};
  device.Write(from_device);
  EXPECT_EQ(ReadAll(port, from_device.size()), from_device);
  const std::vector<uint8_t> to_device = {0xA5, 0x20, 0x0A, 0x0D, 0x03};
  port.Write(to_device.data(), to_device.size());
  std::vector<uint8_t> got;
  for (int tries = 0; got.size() < to_device.size() && tries < 20; ++tries) {
    const std::vector<uint8_t> more = device.Read(100);
    got.insert(got.end(), more.begin(), more.end());
  }
  EXPECT_EQ(got, to_device);
}

TEST(SerialPort, ReadTimesOutWithNothingAndDiscardDropsWaitingBytes) {
  PseudoTerminal device;
  SerialPort port(device.slave_path(), 115200);
  uint8_t byte = 0;
  EXPECT_EQ(port.Read(&byte, 1, 20), 0u);
  device.Write({1, 2, 3});
  usleep(50000);
  port.DiscardInput();
  EXPECT_EQ(port.Read(&byte, 1, 20), 0u);
}

TEST(SerialPort, AnUnpluggedDeviceFailsReadsWithTheName) {
  PseudoTerminal device;
  SerialPort port(device.slave_path(), 115200);
  device.Close();
  uint8_t byte = 0;
  const std::string error = ErrorOf([&] { port.Read(&byte, 1, 200); });
  EXPECT_NE(error.find(device.slave_path()), std::string::npos) << error;
  EXPECT_NE(error.find("gone"), std::string::npos) << error;
}

// A driver that lost its device reopens the port: closing must release the exclusive lock,
// which otherwise stays on a tty another fd holds (this emulator's slave end) and refuses the
// reopen with EBUSY (to any process without CAP_SYS_ADMIN, e.g. in a private namespace).
TEST(SerialPort, ClosingReleasesTheExclusiveLock) {
  PseudoTerminal device;
  { SerialPort port(device.slave_path(), 115200); }
  const int fd = ::open(device.slave_path().c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  ASSERT_GE(fd, 0) << device.slave_path() << ": " << std::strerror(errno);
  int exclusive = -1;
  ASSERT_EQ(::ioctl(fd, TIOCGEXCL, &exclusive), 0) << std::strerror(errno);
  ::close(fd);
  EXPECT_EQ(exclusive, 0);
  SerialPort again(device.slave_path(), 115200);  // and the driver itself can open it again
}

TEST(SerialPort, OpenFailuresNameThePortAndTheCause) {
  const std::string missing = ErrorOf([] { SerialPort("/dev/ttyUSB_aslam_missing", 115200); });
  EXPECT_NE(missing.find("/dev/ttyUSB_aslam_missing"), std::string::npos) << missing;
  EXPECT_NE(missing.find("no such device"), std::string::npos) << missing;
  const std::string not_tty = ErrorOf([] { SerialPort("/dev/null", 115200); });
  EXPECT_NE(not_tty.find("/dev/null"), std::string::npos) << not_tty;
  EXPECT_NE(not_tty.find("not a serial port"), std::string::npos) << not_tty;
  PseudoTerminal device;
  const std::string bad_baud = ErrorOf([&] { SerialPort(device.slave_path(), 0); });
  EXPECT_NE(bad_baud.find("baud"), std::string::npos) << bad_baud;
}

TEST(SerialPort, DtrIsRefusedWithoutModemLines) {
  PseudoTerminal device;
  SerialPort port(device.slave_path(), 115200);
  EXPECT_FALSE(port.SetDtr(true));  // a pseudo-terminal has none; a USB adapter has
}

// A loopback listener on a free port; returns {listening fd, port}.
std::pair<int, int> Listen() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  EXPECT_EQ(::listen(fd, 1), 0);
  socklen_t length = sizeof(address);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  return {fd, ntohs(address.sin_port)};
}

TEST(TcpStream, CarriesBytesAndReportsAClosedPeer) {
  const auto [listener, port] = Listen();
  TcpStream stream("127.0.0.1", port, 1000);
  const int peer = ::accept(listener, nullptr, nullptr);
  ASSERT_GE(peer, 0);
  const std::string request = "VV\n";
  stream.Write(reinterpret_cast<const uint8_t*>(request.data()), request.size());
  char buffer[16] = {};
  ASSERT_EQ(::recv(peer, buffer, sizeof(buffer), 0), static_cast<ssize_t>(request.size()));
  EXPECT_EQ(std::string(buffer, request.size()), request);
  ::send(peer, "VV\n00P\n", 7, 0);
  const std::vector<uint8_t> reply = ReadAll(stream, 7);
  EXPECT_EQ(std::string(reply.begin(), reply.end()), "VV\n00P\n");
  ::close(peer);
  uint8_t byte = 0;
  const std::string error = ErrorOf([&] { stream.Read(&byte, 1, 500); });
  EXPECT_NE(error.find("127.0.0.1:" + std::to_string(port)), std::string::npos) << error;
  EXPECT_NE(error.find("closed"), std::string::npos) << error;
  ::close(listener);
}

TEST(TcpStream, RefusedConnectionNamesHostAndPort) {
  const auto [listener, port] = Listen();
  ::close(listener);  // nothing listens there now
  const std::string error = ErrorOf([port = port] { TcpStream("127.0.0.1", port, 500); });
  EXPECT_NE(error.find("127.0.0.1:" + std::to_string(port)), std::string::npos) << error;
  EXPECT_NE(error.find("refused"), std::string::npos) << error;
}

}  // namespace
}  // namespace aslam
