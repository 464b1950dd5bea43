#include "drivers/emulators/hokuyo_emulator.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "drivers/io/host_clock.h"

namespace aslam::testing {
namespace {

// ---- SCIP 2.0 as the document describes it (independent of the driver's code) ----

// Sum: the low 6 bits of the sum of the bytes, plus 0x30.
char SumOf(const std::string& payload) {
  unsigned total = 0;
  for (unsigned char c : payload) total += c;
  return static_cast<char>((total & 0x3F) + 0x30);
}

// A data or status line: payload, sum, LF.
std::string Line(const std::string& payload) { return payload + SumOf(payload) + "\n"; }

// VV/PP/II lines: "KEY:value;" and the sum of "KEY:value" (the document's examples).
std::string KeyValue(const std::string& key, const std::string& value) {
  const std::string payload = key + ":" + value;
  return payload + ";" + SumOf(payload) + "\n";
}

// `num_chars` characters of 6 bits each, most significant first, each + 0x30.
std::string Characters(uint32_t value, int num_chars) {
  std::string out;
  for (int shift = 6 * (num_chars - 1); shift >= 0; shift -= 6) {
    out.push_back(static_cast<char>(((value >> shift) & 0x3F) + 0x30));
  }
  return out;
}

std::string TwoDigits(int value) {
  char buffer[8];
  std::snprintf(buffer, sizeof(buffer), "%02d", value);
  return buffer;
}

// Decimal digits at [pos, pos + count) of `text`, or -1 if any is not a digit.
int Digits(const std::string& text, std::size_t pos, std::size_t count) {
  if (pos + count > text.size()) return -1;
  int value = 0;
  for (std::size_t i = pos; i < pos + count; ++i) {
    if (text[i] < '0' || text[i] > '9') return -1;
    value = value * 10 + (text[i] - '0');
  }
  return value;
}

constexpr uint32_t kClockModulo = 1u << 24;
constexpr uint32_t kErrorCode = 1;  // what a URG sends for a beam without a valid reading

}  // namespace

const HokuyoModelParameters& ParametersOf(EmulatedHokuyo model) {
  // Sources: see the header.
  static const HokuyoModelParameters urg{
      "URG-04LX-UG01(Hokuyo Automatic Co.,Ltd.)", 20, 5600, 1024, 44, 725, 384, 600};
  static const HokuyoModelParameters ust{"UST-10LX", 20, 30000, 1440, 0, 1080, 540, 2400};
  return model == EmulatedHokuyo::kUrg04lx ? urg : ust;
}

HokuyoEmulator::HokuyoEmulator(HokuyoEmulatorOptions options)
    : options_(std::move(options)), params_(ParametersOf(options_.model)) {
  if (options_.time_scale <= 0) throw std::invalid_argument("time_scale must be > 0");
  PowerOn();
  boot_clock_ms_ = options_.clock_start_ms % kClockModulo;
}

std::unique_ptr<HokuyoEmulator> HokuyoEmulator::OnPseudoTerminal(HokuyoEmulatorOptions options) {
  std::unique_ptr<HokuyoEmulator> e(new HokuyoEmulator(std::move(options)));
  e->pty_ = std::make_unique<PseudoTerminal>();
  e->thread_ = std::thread([raw = e.get()] { raw->Loop(); });
  return e;
}

std::unique_ptr<HokuyoEmulator> HokuyoEmulator::OnTcp(HokuyoEmulatorOptions options) {
  std::unique_ptr<HokuyoEmulator> e(new HokuyoEmulator(std::move(options)));
  e->listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (e->listen_fd_ < 0) throw std::runtime_error("emulator: socket failed");
  const int one = 1;
  ::setsockopt(e->listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // loopback only
  address.sin_port = 0;                              // ephemeral
  if (::bind(e->listen_fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
      ::listen(e->listen_fd_, 4) != 0) {
    throw std::runtime_error(std::string("emulator: bind/listen: ") + std::strerror(errno));
  }
  socklen_t length = sizeof(address);
  ::getsockname(e->listen_fd_, reinterpret_cast<sockaddr*>(&address), &length);
  e->tcp_port_ = ntohs(address.sin_port);
  e->thread_ = std::thread([raw = e.get()] { raw->Loop(); });
  return e;
}

HokuyoEmulator::~HokuyoEmulator() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (client_fd_ >= 0) ::close(client_fd_);
  if (listen_fd_ >= 0) ::close(listen_fd_);
}

std::string HokuyoEmulator::device_path() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pty_ ? pty_->slave_path() : "";
}

void HokuyoEmulator::PowerOn() {
  boot_utime_ = HostClockUtime();
  boot_clock_ms_ = 0;
  scip2_ = !(options_.boot_in_scip11 && options_.model == EmulatedHokuyo::kUrg04lx);
  laser_on_ = false;
  time_adjust_mode_ = false;
  streaming_ = false;
  rb_count_ = 0;
  input_line_.clear();
}

uint32_t HokuyoEmulator::SensorMsAt(int64_t host_utime) const {
  const int64_t elapsed_ms = (host_utime - boot_utime_) / 1000;
  const int64_t ms = (int64_t{boot_clock_ms_} + elapsed_ms) % kClockModulo;
  return static_cast<uint32_t>(ms < 0 ? ms + kClockModulo : ms);
}

uint32_t HokuyoEmulator::SensorClockMs() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return SensorMsAt(HostClockUtime());
}

double HokuyoEmulator::ScanPeriodUs() const {
  return 60.0e6 / params_.scan_rpm / options_.time_scale;
}

// ---- Faults and observations (flags the emulator thread acts on) ----

void HokuyoEmulator::InjectGarbage(const std::string& bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_garbage_ += bytes;
}

void HokuyoEmulator::CorruptNextScanChecksum() {
  std::lock_guard<std::mutex> lock(mutex_);
  corrupt_next_scan_ = true;
}

void HokuyoEmulator::FailNextCommand(const std::string& code, const std::string& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  fail_code_ = code;
  fail_status_ = status;
}

void HokuyoEmulator::InjectScanErrorStatus(const std::string& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  scan_error_status_ = status;
}

void HokuyoEmulator::ResetMidScan() {
  std::lock_guard<std::mutex> lock(mutex_);
  reset_mid_scan_ = true;
}

void HokuyoEmulator::SetGarbageOnly(bool garbage_only) {
  std::lock_guard<std::mutex> lock(mutex_);
  garbage_only_ = garbage_only;
}

void HokuyoEmulator::Unplug() {
  std::unique_lock<std::mutex> lock(mutex_);
  unplug_requested_ = true;
  // The emulator thread closes the descriptors (it may be polling them): wait for it.
  while (unplug_requested_) {
    lock.unlock();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    lock.lock();
  }
}

std::string HokuyoEmulator::Replug() {
  std::unique_lock<std::mutex> lock(mutex_);
  replug_requested_ = true;
  while (replug_requested_) {
    lock.unlock();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    lock.lock();
  }
  return pty_ ? pty_->slave_path() : "";
}

std::vector<std::string> HokuyoEmulator::received_commands() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return received_;
}

std::vector<EmulatedScan> HokuyoEmulator::sent_scans() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sent_;
}

int64_t HokuyoEmulator::scans_sent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int64_t>(sent_.size());
}

int HokuyoEmulator::tcp_connections() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return tcp_connections_;
}

bool HokuyoEmulator::in_scip2() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return scip2_;
}

// ---- The emulator thread ----

void HokuyoEmulator::Loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  uint32_t noise_state = 12345;
  while (!stop_) {
    if (unplug_requested_) {
      if (pty_) pty_->Close();
      if (client_fd_ >= 0) ::close(client_fd_);
      client_fd_ = -1;
      streaming_ = false;
      unplug_requested_ = false;
    }
    if (replug_requested_) {
      if (pty_) pty_ = std::make_unique<PseudoTerminal>();
      PowerOn();
      replug_requested_ = false;
    }

    // Wait for input until the next scan is due (at most 5 ms), without the lock.
    pollfd fds[2];
    int num_fds = 0;
    if (pty_ && pty_->open()) fds[num_fds++] = {pty_->master_fd(), POLLIN, 0};
    if (client_fd_ >= 0) fds[num_fds++] = {client_fd_, POLLIN, 0};
    if (listen_fd_ >= 0) fds[num_fds++] = {listen_fd_, POLLIN, 0};
    int timeout_ms = 5;
    if (streaming_) {
      const int64_t until_scan_ms = (next_scan_utime_ - HostClockUtime()) / 1000;
      timeout_ms = static_cast<int>(std::max<int64_t>(0, std::min<int64_t>(5, until_scan_ms)));
    }
    lock.unlock();
    ::poll(fds, static_cast<nfds_t>(num_fds), timeout_ms);
    lock.lock();

    // New TCP connection: it replaces the current one (a UST serves one client).
    if (listen_fd_ >= 0) {
      const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd >= 0) {
        if (client_fd_ >= 0) ::close(client_fd_);
        client_fd_ = fd;
        ++tcp_connections_;
        streaming_ = false;
        laser_on_ = false;
        input_line_.clear();
      }
    }
    std::vector<uint8_t> input;
    if (pty_ && pty_->open()) input = pty_->Read(0);
    if (client_fd_ >= 0) {
      uint8_t buffer[4096];
      const ssize_t n = ::recv(client_fd_, buffer, sizeof(buffer), MSG_DONTWAIT);
      if (n > 0) {
        input.assign(buffer, buffer + n);
      } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
        ::close(client_fd_);  // the driver hung up: the scan stops
        client_fd_ = -1;
        streaming_ = false;
        laser_on_ = false;
      }
    }
    for (uint8_t byte : input) {
      const char c = static_cast<char>(byte);
      if (c == '\n' || c == '\r') {
        if (!input_line_.empty()) HandleLine(input_line_ + c);
        input_line_.clear();
      } else if (input_line_.size() < 1000) {
        input_line_.push_back(c);
      }
    }

    if (!pending_garbage_.empty()) {
      Send(pending_garbage_);
      pending_garbage_.clear();
    }
    const int64_t now = HostClockUtime();
    if (garbage_only_ && now >= next_noise_utime_) {
      std::string noise;
      for (int i = 0; i < 48; ++i) {
        noise_state = noise_state * 1103515245u + 12345u;
        noise.push_back(static_cast<char>(noise_state >> 16));
      }
      Send(noise);
      next_noise_utime_ = now + 10000;
    }
    SendDueScans();
  }
}

void HokuyoEmulator::Send(const std::string& bytes) {
  if (pty_ && pty_->open()) {
    pty_->Write(std::vector<uint8_t>(bytes.begin(), bytes.end()));
    return;
  }
  std::size_t sent = 0;
  while (client_fd_ >= 0 && sent < bytes.size()) {
    const ssize_t n = ::send(client_fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
    } else if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd p{client_fd_, POLLOUT, 0};
      ::poll(&p, 1, 100);
    } else {
      break;
    }
  }
}

void HokuyoEmulator::HandleLine(const std::string& line) {
  received_.push_back(line);
  if (garbage_only_) return;
  const std::string echo = line.substr(0, line.size() - 1);  // the terminator is not echoed
  if (!scip2_) {
    // SCIP 1.1 knows none of the 2.0 commands but the switch.
    if (echo == "SCIP2.0") {
      scip2_ = true;
      Send(echo + "\n0\n\n");
    } else {
      Send(echo + "\nE\n\n");
    }
    return;
  }
  const std::string code = echo.substr(0, 2);
  if (!fail_code_.empty() && code == fail_code_) {
    Send(echo + "\n" + Line(fail_status_) + "\n");
    fail_code_.clear();
    return;
  }
  if (time_adjust_mode_ && code != "TM") {
    Send(echo + "\n" + Line("0E") + "\n");  // adjust mode takes nothing but TM
    return;
  }
  HandleScip2Command(code, echo);
}

void HokuyoEmulator::HandleScip2Command(const std::string& code, const std::string& echo) {
  const std::string ok = echo + "\n" + Line("00");
  auto status_only = [&](const std::string& status) { Send(echo + "\n" + Line(status) + "\n"); };
  if (code == "VV") {
    const bool urg = options_.model == EmulatedHokuyo::kUrg04lx;
    Send(ok + KeyValue("VEND", "Hokuyo Automatic Co.,Ltd.") +
         KeyValue("PROD", urg ? "SOKUIKI Sensor URG-04LX-UG01" : "SOKUIKI Sensor UST-10LX") +
         KeyValue("FIRM", "3.4.03(17/Dec./2012)") + KeyValue("PROT", "SCIP 2.0") +
         KeyValue("SERI", "H1234567") + "\n");
  } else if (code == "PP") {
    Send(ok + KeyValue("MODL", params_.model) + KeyValue("DMIN", std::to_string(params_.dmin_mm)) +
         KeyValue("DMAX", std::to_string(params_.dmax_mm)) +
         KeyValue("ARES", std::to_string(params_.ares)) +
         KeyValue("AMIN", std::to_string(params_.amin)) +
         KeyValue("AMAX", std::to_string(params_.amax)) +
         KeyValue("AFRT", std::to_string(params_.afrt)) +
         KeyValue("SCAN", std::to_string(params_.scan_rpm)) + "\n");
  } else if (code == "II") {
    char time_hex[16];
    std::snprintf(time_hex, sizeof(time_hex), "%06X", SensorMsAt(HostClockUtime()));
    Send(ok + KeyValue("MODL", params_.model) + KeyValue("LASR", laser_on_ ? "ON" : "OFF") +
         KeyValue("SCSP", "Initial(" + std::to_string(params_.scan_rpm) + "[rpm])") +
         KeyValue("MESM", streaming_ ? "Measuring" : "Idle") + KeyValue("SBPS", "USB only") +
         KeyValue("TIME", time_hex) + KeyValue("STAT", "Sensor works well.") + "\n");
  } else if (code == "BM") {
    status_only(laser_on_ ? "02" : "00");
    laser_on_ = true;
  } else if (code == "QT" || code == "RS") {
    streaming_ = false;
    laser_on_ = false;
    status_only("00");
  } else if (code == "RB") {
    if (++rb_count_ < 2) {
      status_only("01");  // send RB again to reboot
    } else {
      status_only("00");
      PowerOn();
    }
  } else if (code == "TM") {
    const std::string control = echo.substr(2, 1);
    if (control == "0") {
      if (time_adjust_mode_) return status_only("02");
      time_adjust_mode_ = true;
      streaming_ = false;
      laser_on_ = false;
      status_only("00");
    } else if (control == "1") {
      if (!time_adjust_mode_) return status_only("04");
      Send(ok + Line(Characters(SensorMsAt(HostClockUtime()), 4)) + "\n");
    } else if (control == "2") {
      if (!time_adjust_mode_) return status_only("03");
      time_adjust_mode_ = false;
      status_only("00");
    } else {
      status_only("01");
    }
  } else if (code == "MD" || code == "MS") {
    StartScan(code, echo, true);
  } else if (code == "GD" || code == "GS") {
    StartScan(code, echo, false);
  } else {
    status_only("0E");  // undefined command (SCIP2.0 in 2.0 mode included)
  }
}

void HokuyoEmulator::StartScan(const std::string& code, const std::string& echo, bool continuous) {
  auto status_only = [&](const std::string& status) { Send(echo + "\n" + Line(status) + "\n"); };
  const std::size_t params_end = continuous ? 15 : 12;
  if (echo.size() < params_end) return status_only("0C");  // insufficient parameters
  if (echo.size() > params_end && echo[params_end] != ';') return status_only("0C");
  const int start = Digits(echo, 2, 4);
  const int end = Digits(echo, 6, 4);
  const int cluster = Digits(echo, 10, 2);
  if (start < 0) return status_only("01");
  if (end < 0) return status_only("02");
  if (cluster < 0) return status_only("03");
  if (end > params_.amax) return status_only("04");
  if (end < start) return status_only("05");
  const bool two_char = code[1] == 'S';
  if (!continuous) {
    if (!laser_on_) return status_only("10");
    const int64_t now = HostClockUtime();
    const double sweep_us = (end - start + 1) * (ScanPeriodUs() / params_.ares);
    const int64_t beam0 = now - static_cast<int64_t>(sweep_us);
    Send(echo + "\n" + Line("00") +
         ScanData(echo, start, end, cluster, two_char, scan_index_++, beam0, false) + "\n");
    return;
  }
  const int interval = Digits(echo, 12, 1);
  const int scans = Digits(echo, 13, 2);
  if (interval < 0) return status_only("06");
  if (scans < 0) return status_only("07");
  status_only("00");
  laser_on_ = true;
  streaming_ = true;
  stream_echo_prefix_ = echo.substr(0, 13);
  stream_tag_ = echo.substr(15);
  stream_start_ = start;
  stream_end_ = end;
  stream_cluster_ = cluster;
  stream_interval_ = interval;
  stream_remaining_ = scans;
  stream_endless_ = scans == 0;
  stream_two_char_ = two_char;
  next_scan_utime_ = HostClockUtime() + static_cast<int64_t>(ScanPeriodUs());
}

std::string HokuyoEmulator::ScanData(const std::string& echo, int start, int end, int cluster,
                                     bool two_char, int64_t scan_index, int64_t beam0_host_utime,
                                     bool corrupt) {
  const int group = cluster < 1 ? 1 : cluster;
  const uint32_t max_value = two_char ? 4095 : static_cast<uint32_t>(params_.dmax_mm);
  auto reading = [&](int step) -> uint32_t {
    if (step < params_.amin || step > params_.amax) return kErrorCode;
    const double angle_rad = (step - params_.afrt) * 2.0 * M_PI / params_.ares;
    const double r_m = options_.range_m ? options_.range_m(angle_rad, scan_index) : 2.0;
    const long long mm = std::llround(r_m * 1000.0);
    if (r_m <= 0 || mm < params_.dmin_mm || mm > static_cast<long long>(max_value)) {
      return kErrorCode;
    }
    return static_cast<uint32_t>(mm);
  };
  std::string data;
  for (int first = start; first <= end; first += group) {
    // A cluster sends its nearest valid reading (document, MD/MS "Cluster Count").
    uint32_t nearest = 0;
    for (int step = first; step <= std::min(end, first + group - 1); ++step) {
      const uint32_t value = reading(step);
      if (value >= static_cast<uint32_t>(params_.dmin_mm) && (nearest == 0 || value < nearest)) {
        nearest = value;
      }
    }
    data += Characters(nearest == 0 ? kErrorCode : nearest, two_char ? 2 : 3);
  }
  EmulatedScan record;
  record.scan_index = scan_index;
  record.timestamp_ms = SensorMsAt(beam0_host_utime);
  record.beam0_host_utime = beam0_host_utime;
  record.corrupted = corrupt;
  sent_.push_back(record);

  std::string out = Line(Characters(record.timestamp_ms, 4));
  for (std::size_t i = 0; i < data.size(); i += 64) {
    std::string block = Line(data.substr(i, 64));
    if (corrupt && i == 0) {
      char& sum = block[block.size() - 2];
      sum = static_cast<char>(sum == 0x6F ? 0x30 : sum + 1);  // still a SCIP character
    }
    out += block;
  }
  (void)echo;
  return out;
}

void HokuyoEmulator::SendDueScans() {
  const int64_t now = HostClockUtime();
  if (!streaming_ || now < next_scan_utime_) return;
  const double period_us = ScanPeriodUs();
  const int64_t sweep_end = next_scan_utime_;
  const double sweep_us = (stream_end_ - stream_start_ + 1) * (period_us / params_.ares);
  const int64_t beam0 = sweep_end - static_cast<int64_t>(sweep_us);
  next_scan_utime_ += static_cast<int64_t>(period_us * (stream_interval_ + 1));
  if (next_scan_utime_ < now - static_cast<int64_t>(period_us)) {
    next_scan_utime_ = now + static_cast<int64_t>(period_us);  // after a stall: no burst
  }
  if (!scan_error_status_.empty()) {
    Send(stream_echo_prefix_ + TwoDigits(stream_remaining_) + stream_tag_ + "\n" +
         Line(scan_error_status_) + "\n");
    scan_error_status_.clear();
    streaming_ = false;
    laser_on_ = false;
    return;
  }
  if (!stream_endless_) --stream_remaining_;
  const std::string echo = stream_echo_prefix_ + TwoDigits(stream_remaining_) + stream_tag_;
  const std::string body = echo + "\n" + Line("99") +
                           ScanData(echo, stream_start_, stream_end_, stream_cluster_,
                                    stream_two_char_, scan_index_++, beam0, corrupt_next_scan_) +
                           "\n";
  corrupt_next_scan_ = false;
  if (reset_mid_scan_) {
    reset_mid_scan_ = false;
    sent_.back().corrupted = true;  // never complete
    Send(body.substr(0, body.size() / 2));
    PowerOn();  // the sensor reboots: idle, laser off, clock from 0
    return;
  }
  Send(body);
  if (!stream_endless_ && stream_remaining_ <= 0) {
    streaming_ = false;
    laser_on_ = false;
  }
}

}  // namespace aslam::testing
