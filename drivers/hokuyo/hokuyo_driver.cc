#include "drivers/hokuyo/hokuyo_driver.h"

#include "common/robot_config.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "drivers/io/host_clock.h"
#include "drivers/io/serial_port.h"
#include "drivers/io/tcp_stream.h"

namespace aslam {
namespace {

constexpr int kReadChunkMs = 20;          // one Read's wait: short, so timeouts stay accurate
constexpr int kQuietMidResponseMs = 200;  // silence inside a response: the device stopped
constexpr int kMaxSessionRetries = 3;     // protocol failures on one stream before reopening it
constexpr int64_t kTimestampHalfRange = int64_t{1} << 23;

int64_t MsToUs(double ms) { return static_cast<int64_t>(std::llround(ms * 1000.0)); }
int SecondsToMs(double s) { return static_cast<int>(std::lround(s * 1000.0)); }

HokuyoModel ModelFromModl(const std::string& modl) {
  if (modl.find("URG-04LX") != std::string::npos) return HokuyoModel::kUrg04lx;
  if (modl.find("UST-10LX") != std::string::npos) return HokuyoModel::kUst10lx;
  if (modl.find("UST-20LX") != std::string::npos) return HokuyoModel::kUst20lx;
  return HokuyoModel::kAuto;
}

std::string WithoutLineFeed(const std::string& command) {
  return command.empty() || command.back() != '\n' ? command
                                                   : command.substr(0, command.size() - 1);
}

bool IsScanCode(const std::string& code) {
  return code == "MD" || code == "MS" || code == "GD" || code == "GS";
}

std::string Describe(const std::string& command_code, const std::string& status) {
  const std::string meaning = scip::StatusMeaning(command_code, status);
  return command_code + " answered status " + status +
         (meaning.empty() ? "" : " (" + meaning + ")");
}

// An error status in answer to the scan command while scanning (hardware trouble...).
class ScanStatusError : public ScipSessionError {
 public:
  using ScipSessionError::ScipSessionError;
};

void AddParserStats(HokuyoStats* stats, const scip::ParserStats& parser) {
  stats->checksum_errors += parser.checksum_errors;
  stats->partial_packets += parser.partial_packets;
  stats->garbage_bytes += parser.garbage_bytes;
}

}  // namespace

std::optional<HokuyoModel> ParseHokuyoModel(const std::string& name) {
  if (name == "auto") return HokuyoModel::kAuto;
  if (name == "urg04lx") return HokuyoModel::kUrg04lx;
  if (name == "ust10lx") return HokuyoModel::kUst10lx;
  if (name == "ust20lx") return HokuyoModel::kUst20lx;
  return std::nullopt;
}

std::string HokuyoModelName(HokuyoModel model) {
  switch (model) {
    case HokuyoModel::kUrg04lx: return "urg04lx";
    case HokuyoModel::kUst10lx: return "ust10lx";
    case HokuyoModel::kUst20lx: return "ust20lx";
    case HokuyoModel::kAuto: break;
  }
  return "auto";
}

std::string HokuyoOptions::device_name() const {
  return uses_tcp() ? host + ":" + std::to_string(tcp_port) : port;
}

HokuyoOptions LoadHokuyoOptions(const ConfigReader& c) {
  HokuyoOptions o;
  c.Read("port", &o.port);
  c.ReadInRange("baud", &o.baud, 1200, 3000000);
  c.Read("host", &o.host);
  c.ReadInRange("tcp_port", &o.tcp_port, 1, 65535);
  std::string model = HokuyoModelName(o.model);
  c.Read("model", &model);
  const auto parsed = ParseHokuyoModel(model);
  if (!parsed) c.Fail("model", "must be auto, urg04lx, ust10lx or ust20lx");
  o.model = *parsed;
  c.ReadInRange("start_step", &o.start_step, -1, 9999);
  c.ReadInRange("end_step", &o.end_step, -1, 9999);
  if (o.start_step >= 0 && o.end_step >= 0 && o.start_step > o.end_step) {
    c.Fail("end_step", "must not be below start_step");
  }
  c.ReadInRange("cluster_count", &o.cluster_count, 1, 99);
  c.Read("two_char_encoding", &o.two_char_encoding);
  c.Read("poll_single_scans", &o.poll_single_scans);
  c.ReadInRange("time_sync_round_trips", &o.time_sync_round_trips, 1, 100);
  c.ReadInRange("response_timeout_s", &o.response_timeout_s, 0.05, 60.0);
  c.ReadInRange("scan_timeout_s", &o.scan_timeout_s, 0.05, 60.0);
  c.ReadInRange("reconnect_backoff_s", &o.reconnect_backoff_s, 0.01, 600.0);
  c.ReadInRange("reconnect_backoff_max_s", &o.reconnect_backoff_max_s, 0.01, 3600.0);
  if (o.reconnect_backoff_max_s < o.reconnect_backoff_s) {
    c.Fail("reconnect_backoff_max_s", "must not be below reconnect_backoff_s");
  }
  c.ReadInRange("connect_timeout_s", &o.connect_timeout_s, 0.05, 60.0);
  c.CheckAllKeysUsed();
  return o;
}

HokuyoOptions LoadHokuyoOptionsFromFile(const std::string& file) {
  HokuyoOptions options = LoadHokuyoOptions(ConfigReader::FromOptionalFile(file, "hokuyo"));
  options.sensor_pose = LoadRobotOptionsFromFile(file).lidar_mount;
  return options;
}

void ResolveHokuyoTransport(HokuyoOptions* o) {
  if (!o->port.empty() && !o->host.empty()) {
    throw ConfigError("hokuyo: give either port (" + o->port + ", USB serial: URG-04LX) or host (" +
                      o->host + ", Ethernet: UST-10LX/20LX), not both");
  }
  if (o->port.empty() && o->host.empty()) {
    if (o->model == HokuyoModel::kUrg04lx) {
      o->port = "/dev/ttyACM0";
    } else if (o->model == HokuyoModel::kUst10lx || o->model == HokuyoModel::kUst20lx) {
      o->host = "192.168.0.10";  // the UST's factory address
    } else {
      throw ConfigError(
          "hokuyo: no device: give --port /dev/ttyACM0 (URG-04LX over USB) or --host "
          "192.168.0.10 (UST-10LX/20LX over Ethernet), or --model to use its default");
    }
  }
}

// ---- SensorClockMapper ----

void SensorClockMapper::Sync(const std::vector<Sample>& samples) {
  if (samples.empty()) return;
  // Unwrap every sample against the first, so a sync across the 24-bit wrap holds.
  const uint32_t first_raw = samples.front().sensor_ms;
  std::size_t best = 0;
  int64_t best_unwrapped = first_raw;
  int64_t last_unwrapped = first_raw;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    int64_t delta = (samples[i].sensor_ms - first_raw) & (scip::kTimestampModulo - 1);
    if (delta >= kTimestampHalfRange) delta -= scip::kTimestampModulo;
    const int64_t unwrapped = first_raw + delta;
    const int64_t round_trip = samples[i].host_receive_utime - samples[i].host_send_utime;
    const int64_t best_trip = samples[best].host_receive_utime - samples[best].host_send_utime;
    if (i == 0 || round_trip < best_trip) {
      best = i;
      best_unwrapped = unwrapped;
    }
    last_unwrapped = unwrapped;
  }
  const Sample& s = samples[best];
  const int64_t midpoint = s.host_send_utime + (s.host_receive_utime - s.host_send_utime) / 2;
  offset_us_ = midpoint - best_unwrapped * 1000;
  best_round_trip_us_ = s.host_receive_utime - s.host_send_utime;
  last_raw_ms_ = samples.back().sensor_ms;
  last_unwrapped_ms_ = last_unwrapped;
  synced_ = true;
}

int64_t SensorClockMapper::ToHostUtime(uint32_t sensor_ms) {
  int64_t delta = (sensor_ms - last_raw_ms_) & (scip::kTimestampModulo - 1);
  if (delta >= kTimestampHalfRange) delta -= scip::kTimestampModulo;  // a little backwards
  last_unwrapped_ms_ += delta;
  last_raw_ms_ = sensor_ms;
  return offset_us_ + last_unwrapped_ms_ * 1000;
}

int64_t SensorClockMapper::ClampToReceipt(int64_t mapped_utime, int64_t receive_utime) {
  if (mapped_utime <= receive_utime) return mapped_utime;
  offset_us_ -= mapped_utime - receive_utime;
  return receive_utime;
}

// ---- HokuyoSession ----

HokuyoSession::HokuyoSession(ByteStream& stream, const HokuyoOptions& options)
    : stream_(stream), options_(options) {}

void HokuyoSession::Send(const std::string& command) {
  stream_.Write(reinterpret_cast<const uint8_t*>(command.data()), command.size());
}

std::optional<scip::Response> HokuyoSession::NextResponse(int64_t deadline_utime) {
  uint8_t buffer[4096];
  std::vector<scip::Response> parsed;
  while (pending_.empty()) {
    const int64_t now = HostClockUtime();
    if (now >= deadline_utime) return std::nullopt;
    const int wait_ms =
        static_cast<int>(std::min<int64_t>(kReadChunkMs, (deadline_utime - now) / 1000 + 1));
    const std::size_t n = stream_.Read(buffer, sizeof(buffer), wait_ms);
    if (n == 0) {
      if (parser_.in_response() &&
          HostClockUtime() - last_byte_utime_ > kQuietMidResponseMs * 1000) {
        parser_.DropPartial();  // the device went quiet mid-response (reset, unplug, lost bytes)
      }
      continue;
    }
    last_byte_utime_ = HostClockUtime();
    bytes_received_ += static_cast<int64_t>(n);
    parsed.clear();
    parser_.Feed(buffer, n, &parsed);
    for (auto& r : parsed) pending_.push_back(std::move(r));
  }
  scip::Response response = std::move(pending_.front());
  pending_.pop_front();
  return response;
}

std::optional<scip::Response> HokuyoSession::Await(const std::string& command, int timeout_ms) {
  const std::string echo = WithoutLineFeed(command);
  const int64_t deadline = HostClockUtime() + int64_t{timeout_ms} * 1000;
  while (auto response = NextResponse(deadline)) {
    if (response->echo == echo) return response;
    // Anything else (scans still streaming, answers to earlier commands) is skipped.
  }
  return std::nullopt;
}

std::string HokuyoSession::NoAnswerMessage(const std::string& command) const {
  const std::string head = stream_.name() + ": ";
  const std::string what = "no answer to " + WithoutLineFeed(command) + " within " +
                           std::to_string(options_.response_timeout_s).substr(0, 4) + " s";
  if (bytes_received_ == 0) {
    return head + what + ": the device sent nothing (is it a Hokuyo, powered, and is this its " +
           (options_.uses_tcp() ? "address?)" : "port?)");
  }
  if (parser_.stats().responses == 0 && parser_.stats().garbage_bytes > 0) {
    return head + "the device answers, but not in SCIP 2.0: " +
           std::to_string(parser_.stats().garbage_bytes) + " of " +
           std::to_string(bytes_received_) + " bytes were no SCIP response" +
           (options_.uses_tcp() ? " (is this a Hokuyo UST?)"
                                : " (wrong --baud? another device on this port?)");
  }
  return head + what;
}

scip::Response HokuyoSession::Command(const std::string& command) {
  Send(command);
  auto response = Await(command, SecondsToMs(options_.response_timeout_s));
  if (!response) throw ScipSessionError(NoAnswerMessage(command));
  if (!scip::IsSuccess(response->command_code(), response->status)) {
    throw ScipSessionError(stream_.name() + ": " +
                           Describe(response->command_code(), response->status));
  }
  return *response;
}

void HokuyoSession::DiscardPendingInput(int quiet_ms) {
  uint8_t buffer[4096];
  const int64_t give_up = HostClockUtime() + 1000000;  // a device that never stops talking
  while (HostClockUtime() < give_up && stream_.Read(buffer, sizeof(buffer), quiet_ms) > 0) {
  }
  stream_.DiscardInput();
  parser_.DropPartial();
  pending_.clear();
}

const HokuyoInfo& HokuyoSession::Connect() {
  info_ = HokuyoInfo{};
  stream_.DiscardInput();
  const int timeout_ms = SecondsToMs(options_.response_timeout_s);
  // QT stops a scan a previous run left streaming; its answer tells the protocol.
  Send(scip::QuitCommand());
  auto qt = Await(scip::QuitCommand(), timeout_ms);
  if (!qt) {
    Send(scip::Scip2Command());  // a device that ignored QT: try the switch, then QT again
    Await(scip::Scip2Command(), timeout_ms / 2);
    Send(scip::QuitCommand());
    qt = Await(scip::QuitCommand(), timeout_ms);
    if (!qt) throw ScipSessionError(NoAnswerMessage(scip::QuitCommand()));
  }
  if (qt->is_scip11_status()) {
    // A URG-04LX that boots in SCIP 1.1 answers QT with "E": switch it to 2.0.
    info_.was_in_scip11 = true;
    Send(scip::Scip2Command());
    if (!Await(scip::Scip2Command(), timeout_ms)) {
      throw ScipSessionError(stream_.name() + ": answers in SCIP 1.1 and not to SCIP2.0 (" +
                             "switch it to SCIP 2.0 with Hokuyo's URG_Configure)");
    }
    Command(scip::QuitCommand());
  } else if (qt->status == "0E") {
    // Left in time-adjust mode (TM0) by an earlier run: TM2 leaves it.
    Send(scip::TimeCommand(2));
    Await(scip::TimeCommand(2), timeout_ms);
    Command(scip::QuitCommand());
  } else if (!scip::IsSuccess("QT", qt->status)) {
    throw ScipSessionError(stream_.name() + ": " + Describe("QT", qt->status));
  }
  DiscardPendingInput(50);

  info_.version = scip::ParseKeyValues(Command(scip::VersionCommand()));
  try {
    info_.parameters = scip::ParseSensorParameters(Command(scip::ParametersCommand()));
  } catch (const scip::ProtocolError& e) {
    throw ScipSessionError(stream_.name() + ": " + e.what());
  }
  info_.model = ModelFromModl(info_.parameters.model);
  if (options_.model != HokuyoModel::kAuto && info_.model != options_.model) {
    info_.warnings.push_back("configured model " + HokuyoModelName(options_.model) +
                             " but the sensor reports MODL '" + info_.parameters.model +
                             "'; using the sensor's own geometry (PP)");
  }
  info_.state = scip::ParseKeyValues(Command(scip::StateCommand()));
  CheckStepRange();
  return info_;
}

void HokuyoSession::CheckStepRange() {
  const scip::SensorParameters& p = info_.parameters;
  request_ = scip::ScanRequest{};
  request_.start_step = options_.start_step < 0 ? p.first_step : options_.start_step;
  request_.end_step = options_.end_step < 0 ? p.last_step : options_.end_step;
  request_.cluster_count = options_.cluster_count;
  request_.encoding =
      options_.two_char_encoding ? scip::RangeEncoding::kTwoChar : scip::RangeEncoding::kThreeChar;
  if (request_.start_step < p.first_step || request_.end_step > p.last_step ||
      request_.start_step > request_.end_step) {
    throw ScipSessionError(stream_.name() + ": steps " + std::to_string(request_.start_step) +
                           ".." + std::to_string(request_.end_step) +
                           " are outside the sensor's AMIN..AMAX " + std::to_string(p.first_step) +
                           ".." + std::to_string(p.last_step) + " (hokuyo start_step / end_step)");
  }
}

void HokuyoSession::SyncTime() {
  Command(scip::TimeCommand(0));
  std::vector<SensorClockMapper::Sample> samples;
  const int timeout_ms = SecondsToMs(options_.response_timeout_s);
  for (int i = 0; i < options_.time_sync_round_trips; ++i) {
    SensorClockMapper::Sample sample;
    sample.host_send_utime = HostClockUtime();
    Send(scip::TimeCommand(1));
    const auto response = Await(scip::TimeCommand(1), timeout_ms);
    sample.host_receive_utime = HostClockUtime();
    if (!response) throw ScipSessionError(NoAnswerMessage(scip::TimeCommand(1)));
    try {
      sample.sensor_ms = scip::ParseTimeResponse(*response);
    } catch (const scip::ProtocolError& e) {
      throw ScipSessionError(stream_.name() + ": " + e.what());
    }
    samples.push_back(sample);
  }
  Command(scip::TimeCommand(2));
  clock_.Sync(samples);
}

void HokuyoSession::Start() {
  if (options_.poll_single_scans) {
    Command(scip::LaserOnCommand());
    scan_command_ = scip::SingleScanCommand(request_);
    poll_outstanding_ = false;
  } else {
    scan_command_ = scip::ContinuousScanCommand(request_);
    Command(scan_command_);  // "00": accepted; scans follow with status 99
  }
}

std::optional<LidarScan> HokuyoSession::ReadScan(int timeout_ms) {
  const int64_t deadline = HostClockUtime() + int64_t{timeout_ms} * 1000;
  for (;;) {
    if (options_.poll_single_scans) {
      const int64_t now = HostClockUtime();
      const int64_t period_us = MsToUs(info_.parameters.ScanPeriodS() * 1000.0);
      const bool answer_lost =
          poll_outstanding_ && now - poll_sent_utime_ > MsToUs(options_.response_timeout_s * 1e3);
      // One GD per scan period: asking faster returns the same scan again.
      if ((!poll_outstanding_ || answer_lost) && now - poll_sent_utime_ >= period_us) {
        Send(scan_command_);
        poll_sent_utime_ = now;
        poll_outstanding_ = true;
      }
    }
    const int64_t poll_deadline =
        options_.poll_single_scans && !poll_outstanding_
            ? std::min(deadline, poll_sent_utime_ + MsToUs(info_.parameters.ScanPeriodS() * 1000.0))
            : deadline;
    auto response = NextResponse(poll_deadline);
    if (!response) {
      if (HostClockUtime() >= deadline) return std::nullopt;
      continue;
    }
    const std::string code = response->command_code();
    if (!IsScanCode(code)) continue;  // a late answer to something else
    if (code[0] == 'G') poll_outstanding_ = false;
    if (scip::IsScanData(*response)) {
      try {
        return ToLidarScan(scip::ParseScanData(*response), HostClockUtime());
      } catch (const scip::ProtocolError&) {
        ++scans_dropped_;  // malformed data: this scan only
        continue;
      }
    }
    if (response->status == "00") continue;  // MD's acknowledgement
    throw ScanStatusError(stream_.name() + ": while scanning, " + Describe(code, response->status));
  }
}

void HokuyoSession::Stop() {
  try {
    Send(scip::QuitCommand());
    Await(scip::QuitCommand(), 200);
  } catch (const DeviceError&) {
    // Gone already: nothing to stop.
  }
}

LidarScan HokuyoSession::ToLidarScan(const scip::ScanData& data, int64_t receive_utime) {
  const scip::SensorParameters& p = info_.parameters;
  const int cluster = data.cluster_count;
  const double step_rad = 2.0 * M_PI / p.steps_per_turn;
  const double step_time_s = p.ScanPeriodS() / p.steps_per_turn;
  const double cluster_centre_steps = (cluster - 1) / 2.0;  // a cluster's beam: its middle step
  const int max_mm =
      options_.two_char_encoding ? std::min(p.max_distance_mm, 4095) : p.max_distance_mm;
  LidarScan scan;
  scan.sensor_pose = options_.sensor_pose;
  scan.angle_min_rad = p.StepAngleRad(data.start_step + cluster_centre_steps);
  scan.angle_increment_rad = cluster * step_rad;
  scan.range_min_m = p.min_distance_mm * 1e-3;
  scan.range_max_m = max_mm * 1e-3;
  scan.range_m.reserve(data.values_mm.size());
  scan.beam_time_s.reserve(data.values_mm.size());
  for (std::size_t i = 0; i < data.values_mm.size(); ++i) {
    const uint32_t mm = data.values_mm[i];
    // Readings below DMIN are the sensor's error codes, above DMAX out of range: no return.
    const bool valid =
        mm >= static_cast<uint32_t>(p.min_distance_mm) && mm <= static_cast<uint32_t>(max_mm);
    scan.range_m.push_back(valid ? static_cast<float>(mm * 1e-3) : 0.0f);
    scan.beam_time_s.push_back(static_cast<float>(
        (static_cast<double>(i) * cluster + cluster_centre_steps) * step_time_s));
  }
  scan.utime = clock_.ClampToReceipt(clock_.ToHostUtime(data.timestamp_ms), receive_utime);
  return scan;
}

// ---- HokuyoDriver ----

HokuyoDriver::HokuyoDriver(HokuyoOptions options, StreamFactory open_stream)
    : options_(std::move(options)), open_stream_(std::move(open_stream)) {
  if (!open_stream_) {
    const HokuyoOptions o = options_;
    open_stream_ = [o]() -> std::unique_ptr<ByteStream> {
      if (o.uses_tcp()) {
        return std::make_unique<TcpStream>(o.host, o.tcp_port, SecondsToMs(o.connect_timeout_s));
      }
      return std::make_unique<SerialPort>(o.port, o.baud);
    };
  }
  log_ = [](const std::string& message) {
    std::fprintf(stderr, "aslam-hokuyo: %s\n", message.c_str());
  };
}

void HokuyoDriver::Log(const std::string& message) {
  try {
    if (log_) log_(message);
  } catch (...) {
    // A failing logger must not stop the scans.
  }
}

HokuyoStats HokuyoDriver::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

std::string HokuyoDriver::last_error() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_error_;
}

std::optional<HokuyoInfo> HokuyoDriver::info() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return info_;
}

bool HokuyoDriver::SleepUnlessStopped(double seconds, const std::atomic<bool>& stop) {
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::microseconds(static_cast<int64_t>(seconds * 1e6));
  while (!stop && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return !stop;
}

void HokuyoDriver::RunSession(ByteStream& stream, const std::atomic<bool>& stop,
                              const ScanHandler& on_scan) {
  int failures = 0;
  while (!stop) {
    HokuyoSession session(stream, options_);
    HokuyoStats finished;  // the driver's totals before this session
    {
      std::lock_guard<std::mutex> lock(mutex_);
      finished = stats_;
    }
    bool scanning = false;
    auto publish_stats = [&] {
      std::lock_guard<std::mutex> lock(mutex_);
      stats_ = finished;
      AddParserStats(&stats_, session.parser_stats());
      stats_.scans_dropped += session.scans_dropped();
      stats_.connected = scanning && !stop;
      stats_.clock_offset_ms = session.clock().offset_us() * 1e-3;
      stats_.clock_jitter_ms = arrivals_.jitter_ms();
    };
    int64_t session_scans = 0;
    try {
      const HokuyoInfo& info = session.Connect();
      for (const std::string& warning : info.warnings) Log(stream.name() + ": " + warning);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        info_ = info;
      }
      session.SyncTime();
      session.Start();
      const scip::SensorParameters& p = info.parameters;
      Log(stream.name() + ": " + p.model + (info.was_in_scip11 ? " (switched to SCIP 2.0)" : "") +
          ", steps " + std::to_string(p.first_step) + ".." + std::to_string(p.last_step) + " of " +
          std::to_string(p.steps_per_turn) + ", " + std::to_string(p.scan_rpm) +
          " rpm; clock synced (best TM1 round trip " +
          std::to_string(session.clock().best_round_trip_s() * 1e3).substr(0, 5) + " ms); sent " +
          WithoutLineFeed(session.scan_command()));
      int64_t last_scan_utime = HostClockUtime();
      scanning = true;
      while (!stop) {
        auto scan = session.ReadScan(100);
        if (scan) {
          last_scan_utime = HostClockUtime();
          arrivals_.Map(scan->utime, last_scan_utime);
          failures = 0;
          ++session_scans;
          scan->seq = next_seq_++;
          ++finished.scans;
          try {
            on_scan(*scan);
          } catch (const std::exception& e) {
            Log(std::string("scan handler failed (scan dropped): ") + e.what());
          }
        } else if (HostClockUtime() - last_scan_utime > MsToUs(options_.scan_timeout_s * 1e3)) {
          throw ScipSessionError(stream.name() + ": no scan for " +
                                 std::to_string(options_.scan_timeout_s).substr(0, 4) +
                                 " s (the sensor reset or stalled)");
        }
        publish_stats();
      }
      session.Stop();
      publish_stats();
      return;
    } catch (const ScipSessionError& e) {
      scanning = false;
      publish_stats();
      const bool reopen = ++failures >= kMaxSessionRetries;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        last_error_ = e.what();
        if (dynamic_cast<const ScanStatusError*>(&e) != nullptr) ++stats_.error_statuses;
        if (!reopen) ++stats_.reconnects;  // a reopen is counted by Run
      }
      Log(e.what());
      if (reopen) throw;  // reopen the device, with backoff
      Log("restarting the session on " + stream.name());
      if (!SleepUnlessStopped(std::min(options_.reconnect_backoff_s, 0.2), stop)) return;
    } catch (...) {
      scanning = false;
      publish_stats();
      throw;
    }
  }
}

void HokuyoDriver::Run(const std::atomic<bool>& stop, const ScanHandler& on_scan) {
  double backoff_s = options_.reconnect_backoff_s;
  while (!stop) {
    int64_t scans_before = stats().scans;
    try {
      std::unique_ptr<ByteStream> stream = open_stream_();
      RunSession(*stream, stop, on_scan);
    } catch (const std::exception& e) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        last_error_ = e.what();
      }
      if (dynamic_cast<const ScipSessionError*>(&e) == nullptr) Log(e.what());
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      last_error_ = options_.device_name() + ": unknown failure";
    }
    if (stop) break;
    if (stats().scans > scans_before) backoff_s = options_.reconnect_backoff_s;
    Log("reconnecting to " + options_.device_name() + " in " +
        std::to_string(backoff_s).substr(0, 4) + " s");
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++stats_.reconnects;
    }
    if (!SleepUnlessStopped(backoff_s, stop)) break;
    backoff_s = std::min(backoff_s * 2.0, options_.reconnect_backoff_max_s);
  }
}

}  // namespace aslam
