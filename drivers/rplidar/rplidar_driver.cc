#include "drivers/rplidar/rplidar_driver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <thread>

#include "common/robot_config.h"
#include "drivers/io/backoff_config.h"
#include "drivers/io/host_clock.h"
#include "drivers/io/serial_port.h"

namespace aslam {
namespace {

using rplidar::DefaultsFor;
using rplidar::HealthStatus;
using rplidar::Model;
using rplidar::PacketFormat;

constexpr int kExpressFirmware = 0x0111;    // 1.17
constexpr int kLidarConfFirmware = 0x0118;  // 1.24: GET_LIDAR_CONF
// Old firmware ignores GET_LIDAR_CONF: give up on it soon, as the SDK's probe does (250 ms).
constexpr double kLidarConfProbeTimeoutS = 0.25;
// Per-sample angle steps above this are gaps, not sweep (for the coverage check).
constexpr double kMaxSweepStepDeg = 20.0;
// A revolution must sweep this much to be published (a resync or restart cuts it short).
constexpr double kMinRevolutionCoverageDeg = 300.0;
// More than a turn: a start of revolution was missed (lost packets); the sweep is no scan.
constexpr double kMaxRevolutionCoverageDeg = 370.0;

bool IsSeriesS(Model model) { return model == Model::kS1 || model == Model::kS2; }

// EXPRESS_SCAN and GET_SAMPLERATE: A-series from firmware 1.17; S-series (whose firmware
// numbers start again at 1.0x) always.
bool HasExpressScan(Model model, const rplidar::DeviceInfo& info) {
  return IsSeriesS(model) || info.FirmwareNumber() >= kExpressFirmware;
}

bool IsListedModeName(const std::string& scan_mode) {
  const auto& names = rplidar::KnownScanModeNames();
  return std::find(names.begin(), names.end(), scan_mode) != names.end();
}

bool IsValidScanMode(const std::string& scan_mode) {
  return scan_mode == "auto" || scan_mode == "standard" || scan_mode == "express" ||
         IsListedModeName(scan_mode);
}

std::string ScanModeChoices() {
  std::string text = "standard, express, auto";
  for (const std::string& name : rplidar::KnownScanModeNames()) text += ", " + name;
  return text;
}

// The device's mode list is wanted for a mode named by the user, or for auto on A-series
// firmware that has GET_LIDAR_CONF (S-series keep their per-model DenseBoost choice).
bool WantsScanModes(const std::string& scan_mode, Model model, const rplidar::DeviceInfo& info) {
  if (IsListedModeName(scan_mode)) return true;
  return scan_mode == "auto" && !IsSeriesS(model) && info.FirmwareNumber() >= kLidarConfFirmware;
}

void SleepS(double seconds) {
  std::this_thread::sleep_for(std::chrono::microseconds(static_cast<int64_t>(seconds * 1e6)));
}

std::string Hex(const std::vector<uint8_t>& bytes) {
  std::string text;
  char b[4];
  for (const uint8_t v : bytes) {
    std::snprintf(b, sizeof(b), "%02X ", v);
    text += b;
  }
  if (!text.empty()) text.pop_back();
  return text;
}

std::string Hex16(uint16_t value) {
  char b[8];
  std::snprintf(b, sizeof(b), "0x%04X", value);
  return b;
}

double WrapPi(double angle_rad) {
  angle_rad = std::fmod(angle_rad + M_PI, 2.0 * M_PI);
  if (angle_rad < 0) angle_rad += 2.0 * M_PI;
  return angle_rad - M_PI;
}

const char* kBaudHint =
    "A1 and A2M8 talk at 115200 baud, A2M12, A3 and S1 at 256000, S2 at 1000000: set --baud or "
    "rplidar.baud";

}  // namespace

RplidarOptions LoadRplidarOptions(const ConfigReader& c) {
  RplidarOptions o;
  c.Read("port", &o.port);
  c.ReadInRange("baud", &o.baud, 0, 4000000);
  c.Read("model", &o.model);
  if (o.model != "auto" && !rplidar::ParseModelName(o.model)) {
    c.Fail("model", "must be one of a1, a2, a3, s1, s2, auto");
  }
  c.Read("scan_mode", &o.scan_mode);
  if (!IsValidScanMode(o.scan_mode)) c.Fail("scan_mode", "must be one of " + ScanModeChoices());
  c.ReadInRange("beams_per_revolution", &o.beams_per_revolution, 0, 100000);
  c.ReadInRange("range_min_m", &o.range_min_m, 0.0, 100.0);
  c.ReadInRange("range_max_m", &o.range_max_m, 0.0, 100.0);
  if (o.range_max_m > 0 && o.range_min_m >= o.range_max_m) {
    c.Fail("range_min_m", "must be below range_max_m");
  }
  c.ReadInRange("motor_rpm", &o.motor_rpm, 0, 3000);
  ReadReconnectBackoff(c, &o.reconnect_backoff_initial_s, &o.reconnect_backoff_max_s);
  c.ReadInRange("reset_wait_s", &o.reset_wait_s, 0.0, 30.0);
  c.ReadInRange("response_timeout_s", &o.response_timeout_s, 0.01, 30.0);
  c.ReadInRange("stall_timeout_s", &o.stall_timeout_s, 0.05, 60.0);
  c.CheckAllKeysUsed();
  return o;
}

RplidarOptions LoadRplidarOptionsFromFile(const std::string& file) {
  RplidarOptions options = LoadRplidarOptions(ConfigReader::FromOptionalFile(file, "rplidar"));
  options.sensor_pose = LoadRobotOptionsFromFile(file).lidar_mount;
  return options;
}

void ValidateRplidarOptions(const RplidarOptions& o) {
  if (o.port.empty()) throw std::invalid_argument("port is empty (e.g. /dev/rplidar)");
  if (o.baud < 0 || o.baud > 4000000) {
    throw std::invalid_argument("baud " + std::to_string(o.baud) +
                                " is not a serial rate (0 = the model's default)");
  }
  if (o.model != "auto" && !rplidar::ParseModelName(o.model)) {
    throw std::invalid_argument("model '" + o.model + "' is not one of a1, a2, a3, s1, s2, auto");
  }
  if (!IsValidScanMode(o.scan_mode)) {
    throw std::invalid_argument("scan_mode '" + o.scan_mode + "' is not one of " +
                                ScanModeChoices());
  }
  if (o.reconnect_backoff_initial_s <= 0 ||
      o.reconnect_backoff_max_s < o.reconnect_backoff_initial_s) {
    throw std::invalid_argument("reconnect backoff must be 0 < initial <= max");
  }
}

int ResolvedBaud(const RplidarOptions& o) {
  if (o.baud > 0) return o.baud;
  const auto model = rplidar::ParseModelName(o.model);
  return model ? DefaultsFor(*model).baud : 115200;
}

RplidarDriver::RplidarDriver(ByteStream& stream, RplidarOptions options, int baud, SetDtr set_dtr,
                             Log log)
    : stream_(stream),
      options_(std::move(options)),
      baud_(baud > 0 ? baud : 115200),
      set_dtr_(std::move(set_dtr)),
      log_(std::move(log)) {
  if (!log_) {
    log_ = [](const std::string& line) {
      std::fprintf(stderr, "%s\n", line.c_str());
      std::fflush(stderr);
    };
  }
}

void RplidarDriver::Fail(const std::string& what) const {
  throw DeviceError("RPLIDAR on " + stream_.name() + ": " + what);
}

void RplidarDriver::Send(const std::vector<uint8_t>& request) {
  stream_.Write(request.data(), request.size());
}

std::size_t RplidarDriver::ReadIntoBuffer(int timeout_ms) {
  uint8_t chunk[4096];
  const std::size_t n = stream_.Read(chunk, sizeof(chunk), timeout_ms);
  rx_.insert(rx_.end(), chunk, chunk + n);
  return n;
}

std::optional<rplidar::ResponseDescriptor> RplidarDriver::WaitDescriptor(double timeout_s,
                                                                         std::size_t* noise_bytes) {
  const int64_t deadline = HostClockUtime() + static_cast<int64_t>(timeout_s * 1e6);
  for (;;) {
    // Drop everything before the first A5 5A: leftovers of a scan, a boot banner, noise.
    std::size_t start = 0;
    while (start + 1 < rx_.size() &&
           !(rx_[start] == rplidar::kResponseSync1 && rx_[start + 1] == rplidar::kResponseSync2)) {
      ++start;
    }
    if (start + 1 >= rx_.size() && !rx_.empty() && rx_.back() != rplidar::kResponseSync1) {
      start = rx_.size();
    }
    *noise_bytes += start;
    rx_.erase(rx_.begin(), rx_.begin() + static_cast<std::ptrdiff_t>(start));
    if (rx_.size() >= rplidar::kDescriptorSize) {
      const auto descriptor = rplidar::ParseDescriptor(rx_.data());
      rx_.erase(rx_.begin(), rx_.begin() + rplidar::kDescriptorSize);
      return descriptor;
    }
    const int64_t left_us = deadline - HostClockUtime();
    if (left_us <= 0) return std::nullopt;
    ReadIntoBuffer(static_cast<int>(std::min<int64_t>(left_us / 1000 + 1, 100)));
  }
}

std::optional<std::vector<uint8_t>> RplidarDriver::Request(uint8_t command, uint8_t data_type,
                                                           std::size_t min_length,
                                                           std::size_t* noise_bytes) {
  return Request(rplidar::EncodeRequest(command), data_type, min_length, noise_bytes);
}

std::optional<std::vector<uint8_t>> RplidarDriver::Request(const std::vector<uint8_t>& request,
                                                           uint8_t data_type,
                                                           std::size_t min_length,
                                                           std::size_t* noise_bytes,
                                                           double timeout_s) {
  Send(request);
  if (timeout_s <= 0) timeout_s = options_.response_timeout_s;
  const int64_t deadline = HostClockUtime() + static_cast<int64_t>(timeout_s * 1e6);
  for (;;) {
    const double left_s = (deadline - HostClockUtime()) * 1e-6;
    if (left_s <= 0) return std::nullopt;
    const auto descriptor = WaitDescriptor(left_s, noise_bytes);
    if (!descriptor) return std::nullopt;
    if (descriptor->data_type != data_type || descriptor->length < min_length) {
      *noise_bytes += rplidar::kDescriptorSize;  // not our answer: keep looking
      continue;
    }
    while (rx_.size() < descriptor->length) {
      const int64_t left_us = deadline - HostClockUtime();
      if (left_us <= 0) return std::nullopt;
      ReadIntoBuffer(static_cast<int>(std::min<int64_t>(left_us / 1000 + 1, 100)));
    }
    std::vector<uint8_t> data(rx_.begin(), rx_.begin() + descriptor->length);
    rx_.erase(rx_.begin(), rx_.begin() + descriptor->length);
    return data;
  }
}

void RplidarDriver::StopAndFlush() {
  Send(rplidar::EncodeRequest(rplidar::command::kStop));
  // The document asks for >= 1 ms after STOP; a scan in flight may still drain: wait a bit.
  SleepS(0.02);
  stream_.DiscardInput();
  rx_.clear();
}

void RplidarDriver::ResetDevice() {
  Send(rplidar::EncodeRequest(rplidar::command::kReset));
  // The device reboots (A-series print a banner, S1 stays silent) and ignores requests meanwhile.
  SleepS(options_.reset_wait_s);
  stream_.DiscardInput();
  rx_.clear();
}

void RplidarDriver::Connect() {
  StopAndFlush();
  std::size_t noise = 0;
  std::optional<std::vector<uint8_t>> info_bytes;
  for (int attempt = 0; attempt < 2 && !info_bytes; ++attempt) {
    info_bytes = Request(rplidar::command::kGetInfo, rplidar::answer::kDeviceInfo,
                         rplidar::kDeviceInfoSize, &noise);
  }
  if (!info_bytes) {
    char timeout[32];
    std::snprintf(timeout, sizeof(timeout), "%.1f", options_.response_timeout_s);
    const std::string what = "no answer to GET_INFO (A5 50) within 2 x " + std::string(timeout) +
                             " s at " + std::to_string(baud_) + " baud: ";
    if (noise > 0) {
      Fail(what + std::to_string(noise) +
           " bytes arrived that are not RPLIDAR answers, so the baud rate is probably wrong (" +
           kBaudHint + ")");
    }
    Fail(what + "nothing arrived (is the lidar powered, its cable in, the port right? " +
         kBaudHint + ")");
  }
  RplidarConnection& c = connection_;
  c.info = *rplidar::ParseDeviceInfo(info_bytes->data(), info_bytes->size());
  const Model reported = rplidar::ModelFromInfoByte(c.info.model);
  if (options_.model == "auto") {
    c.model = reported;
    if (reported == Model::kUnknown) {
      log_("aslam-rplidar: " + stream_.name() + ": unknown model byte " + Hex({c.info.model}) +
           "; using generic defaults (set rplidar.model to choose)");
    }
  } else {
    c.model = *rplidar::ParseModelName(options_.model);
    if (reported != c.model) {
      log_("aslam-rplidar: " + stream_.name() + ": configured model " + options_.model +
           " but the device reports model byte " + Hex({c.info.model}) + " (" +
           rplidar::ModelName(reported) + "); using " + options_.model);
    }
  }

  noise = 0;
  auto health_bytes = Request(rplidar::command::kGetHealth, rplidar::answer::kDeviceHealth,
                              rplidar::kDeviceHealthSize, &noise);
  auto health = health_bytes
                    ? rplidar::ParseDeviceHealth(health_bytes->data(), health_bytes->size())
                    : std::nullopt;
  if (!health) Fail("no valid answer to GET_HEALTH (A5 52)");
  if (health->status == HealthStatus::kError) {
    log_("aslam-rplidar: " + stream_.name() + ": the lidar reports a hardware error (code " +
         Hex16(health->error_code) + "); sending RESET and checking again");
    ResetDevice();
    StopAndFlush();
    health_bytes = Request(rplidar::command::kGetHealth, rplidar::answer::kDeviceHealth,
                           rplidar::kDeviceHealthSize, &noise);
    health = health_bytes ? rplidar::ParseDeviceHealth(health_bytes->data(), health_bytes->size())
                          : std::nullopt;
    if (!health) Fail("no valid answer to GET_HEALTH after RESET");
    if (health->status == HealthStatus::kError) {
      Fail("the lidar still reports a hardware error (health status error, code " +
           Hex16(health->error_code) +
           ") after a RESET: power-cycle it, check that nothing blocks the rotor, and ask "
           "Slamtec support if it stays");
    }
  }
  if (health->status == HealthStatus::kWarning) {
    log_("aslam-rplidar: " + stream_.name() + ": the lidar reports a health WARNING (code " +
         Hex16(health->error_code) + "); continuing");
  }
  c.health = *health;

  // Sample durations: GET_SAMPLERATE from firmware 1.17; the SDK's 476 us before that.
  c.sample_rate = rplidar::SampleRate{476, 476};
  if (HasExpressScan(c.model, c.info)) {
    const auto rate_bytes = Request(rplidar::command::kGetSampleRate, rplidar::answer::kSampleRate,
                                    rplidar::kSampleRateSize, &noise);
    const auto rate = rate_bytes ? rplidar::ParseSampleRate(rate_bytes->data(), rate_bytes->size())
                                 : std::nullopt;
    if (rate) {
      c.sample_rate = *rate;
    } else {
      log_("aslam-rplidar: " + stream_.name() +
           ": no answer to GET_SAMPLERATE; assuming 476 us per sample");
    }
  }

  c.scan_modes.clear();
  c.typical_scan_mode.reset();
  if (WantsScanModes(options_.scan_mode, c.model, c.info)) ListScanModes();
}

std::optional<std::vector<uint8_t>> RplidarDriver::GetLidarConf(
    uint32_t type, std::optional<uint16_t> scan_mode_id, double timeout_s) {
  std::size_t noise = 0;
  const auto data = Request(rplidar::EncodeGetLidarConfRequest(type, scan_mode_id),
                            rplidar::answer::kLidarConf, 4, &noise, timeout_s);
  if (!data) return std::nullopt;
  return rplidar::ParseLidarConfValue(type, data->data(), data->size());
}

void RplidarDriver::ListScanModes() {
  namespace conf = rplidar::lidar_conf;
  RplidarConnection& c = connection_;
  const auto give_up = [&](const std::string& why) {
    log_("aslam-rplidar: " + stream_.name() + ": " + why + "; using the model's scan mode choice");
    c.scan_modes.clear();
    c.typical_scan_mode.reset();
    // A late or partial answer must not be taken for the scan's response descriptor.
    stream_.DiscardInput();
    rx_.clear();
  };
  const double probe_timeout_s = std::min(options_.response_timeout_s, kLidarConfProbeTimeoutS);
  const auto count_value = GetLidarConf(conf::kScanModeCount, std::nullopt, probe_timeout_s);
  const auto count = count_value ? rplidar::LidarConfUnsigned(*count_value, 2) : std::nullopt;
  if (!count || *count == 0) {
    give_up("no valid answer to GET_LIDAR_CONF (scan mode count)");
    return;
  }
  std::vector<rplidar::ScanMode> modes;
  for (uint32_t id = 0; id < *count; ++id) {
    const auto mode_id = static_cast<uint16_t>(id);
    const auto us = GetLidarConf(conf::kScanModeUsPerSample, mode_id, 0.0);
    const auto max_distance = GetLidarConf(conf::kScanModeMaxDistance, mode_id, 0.0);
    const auto answer_type = GetLidarConf(conf::kScanModeAnswerType, mode_id, 0.0);
    const auto name = GetLidarConf(conf::kScanModeName, mode_id, 0.0);
    if (!us || !max_distance || !answer_type || !name) {
      give_up("no answer to GET_LIDAR_CONF for scan mode " + std::to_string(id));
      return;
    }
    const std::optional<double> us_value = rplidar::LidarConfQ8(*us);
    const std::optional<double> max_value = rplidar::LidarConfQ8(*max_distance);
    const std::optional<uint32_t> type_value = rplidar::LidarConfUnsigned(*answer_type, 1);
    if (!us_value || *us_value <= 0 || !max_value || !type_value) {
      give_up("malformed GET_LIDAR_CONF answers for scan mode " + std::to_string(id));
      return;
    }
    rplidar::ScanMode mode;
    mode.id = mode_id;
    mode.us_per_sample = *us_value;
    mode.max_distance_m = *max_value;
    mode.answer_type = static_cast<uint8_t>(*type_value);
    mode.name = rplidar::LidarConfText(*name);
    modes.push_back(mode);
  }
  const auto typical_value = GetLidarConf(conf::kScanModeTypical, std::nullopt, 0.0);
  const auto typical = typical_value ? rplidar::LidarConfUnsigned(*typical_value, 2) : std::nullopt;
  if (!typical || *typical >= *count) {
    give_up("no valid typical scan mode in GET_LIDAR_CONF");
    return;
  }
  c.scan_modes = std::move(modes);
  c.typical_scan_mode = static_cast<uint16_t>(*typical);
  std::string listing;
  for (const rplidar::ScanMode& mode : c.scan_modes) {
    char entry[160];
    std::snprintf(entry, sizeof(entry), "%s%s (id %u, %.1f us, %.1f m, answer 0x%02X)",
                  listing.empty() ? "" : ", ", mode.name.c_str(), mode.id, mode.us_per_sample,
                  mode.max_distance_m, mode.answer_type);
    listing += entry;
  }
  log_("aslam-rplidar: " + stream_.name() + ": scan modes " + listing + "; typical " +
       c.scan_modes[*c.typical_scan_mode].name);
}

void RplidarDriver::MotorOn() {
  const rplidar::ModelDefaults& model = DefaultsFor(connection_.model);
  if (model.motor == rplidar::MotorControl::kSpeedCommand) {
    Send(rplidar::EncodeMotorSpeedRequest(static_cast<uint16_t>(options_.motor_rpm)));
    return;
  }
  // Slamtec's USB adapter enables the motor while DTR is NOT asserted (the SDK clears DTR
  // to start it, sets DTR to stop it). A port without modem lines cannot: the motor then
  // follows the adapter's default.
  if (set_dtr_) set_dtr_(false);
}

void RplidarDriver::StartStream() {
  RplidarConnection& c = connection_;
  const rplidar::ModelDefaults& model = DefaultsFor(c.model);
  // A mode of the device's list to scan in: the one named, or for auto the typical one.
  const rplidar::ScanMode* listed = nullptr;
  if (IsListedModeName(options_.scan_mode)) {
    if (c.scan_modes.empty()) {
      Fail("scan_mode " + options_.scan_mode + " needs a lidar that lists its scan modes " +
           "(GET_LIDAR_CONF, A-series firmware 1.24 or later), and this one (firmware " +
           c.info.FirmwareText() + ") did not: set scan_mode standard, express or auto");
    }
    std::string names;
    for (const rplidar::ScanMode& mode : c.scan_modes) {
      if (rplidar::ScanModeNameMatches(mode.name, options_.scan_mode)) listed = &mode;
      names += (names.empty() ? "" : ", ") + mode.name;
    }
    if (!listed) {
      Fail("scan_mode " + options_.scan_mode + " is not among the lidar's scan modes (" + names +
           ")");
    }
  } else if (options_.scan_mode == "auto" && c.typical_scan_mode) {
    listed = &c.scan_modes[*c.typical_scan_mode];
  }

  bool express = false;
  std::vector<uint8_t> request;
  std::optional<uint8_t> expected_type;  // a listed mode says how it answers
  double period_us = 0.0;
  double mode_max_distance_m = 0.0;
  if (listed) {
    if (!rplidar::PacketFormatForAnswer(listed->answer_type)) {
      Fail("scan mode " + listed->name + " answers with data type " + Hex({listed->answer_type}) +
           ", which this driver does not decode: choose another " + "scan_mode");
    }
    // The SDK starts a mode answering with plain nodes by SCAN, any other by EXPRESS_SCAN.
    express = listed->answer_type != rplidar::answer::kMeasurement;
    request = express ? rplidar::EncodeExpressScanRequest(static_cast<uint8_t>(listed->id))
                      : rplidar::EncodeRequest(rplidar::command::kScan);
    expected_type = listed->answer_type;
    period_us = listed->us_per_sample;
    mode_max_distance_m = listed->max_distance_m;
    c.scan_mode_name = listed->name;
  } else {
    const bool has_express = HasExpressScan(c.model, c.info);
    express = options_.scan_mode == "express" || (options_.scan_mode == "auto" && has_express);
    if (express && !has_express) {
      Fail("firmware " + c.info.FirmwareText() +
           " has no EXPRESS_SCAN (it needs 1.17 or later): set scan_mode standard");
    }
    request = express ? rplidar::EncodeExpressScanRequest(model.express_working_mode)
                      : rplidar::EncodeRequest(rplidar::command::kScan);
    period_us = express ? c.sample_rate.express_us : c.sample_rate.standard_us;
    c.scan_mode_name = express ? "express" : "standard";
  }
  MotorOn();
  Send(request);
  std::size_t noise = 0;
  const auto descriptor = WaitDescriptor(options_.response_timeout_s, &noise);
  if (!descriptor) Fail("no response descriptor after " + Hex(request));
  const auto format = rplidar::PacketFormatForAnswer(descriptor->data_type);
  if (!format) {
    Fail("answered " + Hex(request) + " with data type " + Hex({descriptor->data_type}) +
         ", which is not a scan answer this driver decodes");
  }
  std::size_t expected_length = rplidar::kCapsuleSize;
  if (*format == PacketFormat::kStandardNodes) expected_length = rplidar::kNodeSize;
  if (*format == PacketFormat::kUltraCapsules) expected_length = rplidar::kUltraCapsuleSize;
  if (descriptor->send_mode != rplidar::SendMode::kMultiple ||
      descriptor->length != expected_length ||
      (!express && *format != PacketFormat::kStandardNodes) ||
      (expected_type && descriptor->data_type != *expected_type)) {
    Fail("unexpected response descriptor to " + Hex(request) + ": " +
         Hex(rplidar::EncodeDescriptor(*descriptor)));
  }
  c.format = *format;
  c.sample_period_s = period_us * 1e-6;
  if (options_.beams_per_revolution > 0) {
    c.beams_per_revolution = options_.beams_per_revolution;
  } else {
    // Samples in one revolution at the model's nominal scan rate, to the nearest ten.
    const double samples = 1.0 / (c.sample_period_s * model.rotation_hz);
    c.beams_per_revolution = std::max(10, static_cast<int>(std::lround(samples / 10.0)) * 10);
  }
  c.range_min_m = options_.range_min_m > 0 ? options_.range_min_m : model.range_min_m;
  c.range_max_m = options_.range_max_m > 0 ? options_.range_max_m : model.range_max_m;
  // A listed mode knows its own reach (A3: 25 m in Sensitivity, 16 m in Standard).
  if (options_.range_max_m <= 0 && mode_max_distance_m > 0) c.range_max_m = mode_max_distance_m;

  if (parser_) {
    stats_.checksum_errors += parser_->checksum_errors();
    stats_.discarded_bytes += parser_->discarded_bytes();
  }
  parser_.emplace(*format);
  arrivals_.clear();
  revolution_.clear();
  in_revolution_ = false;
  last_sample_utime_ = HostClockUtime();
  if (!rx_.empty()) {
    // Bytes that came with the descriptor are the first packets.
    std::vector<rplidar::ScanSample> samples;
    const std::vector<uint8_t> first = std::move(rx_);
    rx_.clear();
    parser_->Feed(first.data(), first.size(), &samples);
    arrivals_.push_back({parser_->stream_offset(), HostClockUtime()});
    std::vector<LidarScan> ignored;  // no whole revolution fits in one read
    Handle(samples, &ignored);
  }
}

void RplidarDriver::Start() {
  Connect();
  StartStream();
  const RplidarConnection& c = connection_;
  char line[512];
  std::snprintf(line, sizeof(line),
                "aslam-rplidar: %s: RPLIDAR %s (model byte 0x%02X, firmware %s, hardware %u, "
                "serial %s), health %s, scan mode %s: %s at %.1f us per sample, %d beams per "
                "revolution, %d baud",
                stream_.name().c_str(), rplidar::ModelName(c.model), c.info.model,
                c.info.FirmwareText().c_str(), c.info.hardware, c.info.SerialText().c_str(),
                rplidar::HealthStatusName(c.health.status), c.scan_mode_name.c_str(),
                rplidar::PacketFormatName(c.format), c.sample_period_s * 1e6,
                c.beams_per_revolution, baud_);
  log_(line);
}

void RplidarDriver::Stop() noexcept {
  try {
    Send(rplidar::EncodeRequest(rplidar::command::kStop));
    if (DefaultsFor(connection_.model).motor == rplidar::MotorControl::kSpeedCommand) {
      Send(rplidar::EncodeMotorSpeedRequest(0));
    } else if (set_dtr_) {
      set_dtr_(true);
    }
  } catch (const std::exception&) {
    // The device is gone: nothing to stop.
  }
}

void RplidarDriver::Poll(int timeout_ms, std::vector<LidarScan>* scans) {
  uint8_t chunk[4096];
  std::vector<rplidar::ScanSample> samples;
  int64_t now = HostClockUtime();
  // Drain what is waiting (up to a bound) so a fast lidar never overflows the port's buffer.
  for (int reads = 0; reads < 64; ++reads) {
    const std::size_t n = stream_.Read(chunk, sizeof(chunk), reads == 0 ? timeout_ms : 0);
    now = HostClockUtime();
    if (n == 0 || !parser_) break;
    samples.clear();
    parser_->Feed(chunk, n, &samples);
    arrivals_.push_back({parser_->stream_offset(), now});
    while (arrivals_.size() > 256) arrivals_.pop_front();
    Handle(samples, scans);
    if (n < sizeof(chunk)) break;
  }
  if (now - last_sample_utime_ > static_cast<int64_t>(options_.stall_timeout_s * 1e6)) {
    // Silence while scanning: the device reset itself (brown-out, RESET) or stopped.
    char line[256];
    std::snprintf(line, sizeof(line),
                  "aslam-rplidar: %s: no measurements for %.1f s; restarting the scan",
                  stream_.name().c_str(), (now - last_sample_utime_) * 1e-6);
    log_(line);
    ++stats_.restarts;
    if (in_revolution_) ++stats_.dropped_revolutions;
    Start();
  }
}

int64_t RplidarDriver::ArrivalUtime(uint64_t offset) const {
  const double byte_us = 10.0 * 1e6 / baud_;  // 8N1: 10 bits per byte
  // The chunk holding `offset`: the first whose end is at or past it (offsets are recent).
  const auto chunk =
      std::lower_bound(arrivals_.begin(), arrivals_.end(), offset,
                       [](const ChunkArrival& a, uint64_t value) { return a.end_offset < value; });
  if (chunk == arrivals_.end()) {
    return arrivals_.empty() ? HostClockUtime() : arrivals_.back().host_utime;
  }
  return chunk->host_utime -
         static_cast<int64_t>(std::llround((chunk->end_offset - offset) * byte_us));
}

void RplidarDriver::Handle(const std::vector<rplidar::ScanSample>& samples,
                           std::vector<LidarScan>* scans) {
  if (samples.empty()) return;
  last_sample_utime_ = HostClockUtime();
  const double byte_us = 10.0 * 1e6 / baud_;
  const double period_us = connection_.sample_period_s * 1e6;
  for (const rplidar::ScanSample& s : samples) {
    if (s.start_of_revolution) {
      if (in_revolution_) FinishRevolution(scans);
      revolution_.clear();
      in_revolution_ = true;
    }
    if (!in_revolution_) continue;
    // The packet left the device when its last byte arrived minus its transfer time; each
    // sample was measured a sample period before the next one in it.
    const double measured = static_cast<double>(ArrivalUtime(s.packet_end_offset)) -
                            s.packet_size * byte_us - s.samples_after_in_packet * period_us;
    revolution_.push_back(
        {s.angle_cw_deg, s.distance_m, s.slot, static_cast<int64_t>(std::llround(measured))});
    if (s.samples_after_in_packet == 0) {  // a packet's last sample, timed by its arrival
      sample_clock_.Map(std::llround(static_cast<double>(s.slot) * period_us),
                        ArrivalUtime(s.packet_end_offset));
    }
    if (revolution_.size() > 200000) {  // no start flag for far too long: start over
      revolution_.clear();
      in_revolution_ = false;
      ++stats_.dropped_revolutions;
    }
  }
}

void RplidarDriver::FinishRevolution(std::vector<LidarScan>* scans) {
  const RplidarConnection& c = connection_;
  if (revolution_.size() < 2) {
    ++stats_.dropped_revolutions;
    return;
  }
  // Coverage: the sum of plausible per-sample steps; garbage or a restart leaves a short sweep.
  double coverage_deg = 0.0;
  for (std::size_t k = 1; k < revolution_.size(); ++k) {
    const double step =
        std::fmod(revolution_[k].angle_cw_deg - revolution_[k - 1].angle_cw_deg + 360.0, 360.0);
    if (step < kMaxSweepStepDeg) coverage_deg += step;
  }
  if (coverage_deg < kMinRevolutionCoverageDeg || coverage_deg > kMaxRevolutionCoverageDeg) {
    ++stats_.dropped_revolutions;
    return;
  }
  const int beams = c.beams_per_revolution;
  const double increment_rad = 2.0 * M_PI / beams;
  const double period_s = c.sample_period_s;
  const RevolutionSample& first = revolution_.front();
  LidarScan scan;
  scan.seq = seq_++;
  scan.sensor_pose = options_.sensor_pose;
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = increment_rad;
  scan.range_min_m = c.range_min_m;
  scan.range_max_m = c.range_max_m;
  scan.range_m.assign(beams, 0.0f);
  scan.beam_time_s.assign(beams, 0.0f);
  std::vector<double> best_offset_rad(beams, std::numeric_limits<double>::infinity());
  int64_t first_utime = std::numeric_limits<int64_t>::max();
  for (const RevolutionSample& s : revolution_) {
    const double since_first_s = static_cast<double>(s.slot - first.slot) * period_s;
    // The least delayed arrival bounds the true time best: reads only ever come late.
    first_utime =
        std::min(first_utime, s.measured_utime - static_cast<int64_t>(since_first_s * 1e6));
    if (!(s.distance_m >= c.range_min_m && s.distance_m <= c.range_max_m)) continue;
    // RPLIDAR angles turn clockwise from the front; LidarScan angles counter-clockwise
    // (REP-103): the beam angle is the negated device angle, wrapped into [-pi, pi).
    const double angle_rad = WrapPi(-s.angle_cw_deg * M_PI / 180.0);
    const int beam = static_cast<int>(std::lround((angle_rad + M_PI) / increment_rad)) % beams;
    const double offset_rad = std::fabs(WrapPi(angle_rad - (-M_PI + beam * increment_rad)));
    if (offset_rad < best_offset_rad[beam]) {
      best_offset_rad[beam] = offset_rad;
      scan.range_m[beam] = static_cast<float>(s.distance_m);
      scan.beam_time_s[beam] = static_cast<float>(since_first_s);
    }
  }
  // Beams without a return get the time the rotor pointed there: their share of the sweep.
  const double sweep_s = static_cast<double>(revolution_.back().slot - first.slot + 1) * period_s;
  for (int beam = 0; beam < beams; ++beam) {
    if (std::isfinite(best_offset_rad[beam])) continue;
    const double cw_deg = std::fmod(-(-M_PI + beam * increment_rad) * 180.0 / M_PI + 720.0, 360.0);
    const double swept = std::fmod(cw_deg - first.angle_cw_deg + 360.0, 360.0) / 360.0;
    scan.beam_time_s[beam] = static_cast<float>(swept * sweep_s);
  }
  scan.utime = first_utime;
  ++stats_.revolutions;
  revolutions_.Count(HostClockUtime());
  scans->push_back(std::move(scan));
}

DriverStatus RplidarDriver::driver_status() const {
  const RplidarStats s = stats();
  DriverStatus status;
  status.utime = HostClockUtime();
  status.driver = "aslam-rplidar";
  status.device = stream_.name();
  status.connected = true;
  status.messages = s.revolutions;
  status.rate_hz = revolutions_.rate_hz(status.utime);
  status.clock_offset_ms = sample_clock_.offset_ms();
  status.clock_jitter_ms = sample_clock_.jitter_ms();
  status.errors = s.checksum_errors + s.dropped_revolutions;
  return status;
}

RplidarStats RplidarDriver::stats() const {
  RplidarStats s = stats_;
  if (parser_) {
    s.checksum_errors += parser_->checksum_errors();
    s.discarded_bytes += parser_->discarded_bytes();
  }
  return s;
}

int64_t RunRplidarLoop(const RplidarOptions& options, const std::atomic<bool>& stop,
                       const std::function<void(const LidarScan&)>& on_scan,
                       const RplidarDriver::Log& log_in, int max_attempts,
                       const std::function<void(const DriverStatus&)>& on_status) {
  const RplidarDriver::Log log = log_in ? log_in : [](const std::string& line) {
    std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
  };
  const int baud = ResolvedBaud(options);
  double backoff_s = options.reconnect_backoff_initial_s;
  int failures = 0;
  int failed_attempts = 0;
  int64_t delivered = 0;
  int64_t next_status_utime = 0;
  std::string last_error;
  // Once a second: the driver's status while connected, else what the loop knows.
  auto report = [&](const RplidarDriver* driver) {
    if (!on_status || HostClockUtime() < next_status_utime) return;
    next_status_utime = HostClockUtime() + 1000000;
    DriverStatus status;
    if (driver != nullptr) {
      status = driver->driver_status();
    } else {
      status.utime = HostClockUtime();
      status.driver = "aslam-rplidar";
      status.device = options.port;
    }
    status.messages = delivered;
    status.reconnects = failed_attempts;
    if (driver == nullptr) status.detail = last_error;
    on_status(status);
  };
  while (!stop) {
    try {
      SerialPort port(options.port, baud);
      RplidarDriver driver(
          port, options, baud, [&port](bool asserted) { return port.SetDtr(asserted); }, log);
      driver.Start();
      failures = 0;
      backoff_s = options.reconnect_backoff_initial_s;
      std::vector<LidarScan> scans;
      while (!stop) {
        scans.clear();
        driver.Poll(100, &scans);
        for (const LidarScan& scan : scans) {
          on_scan(scan);
          ++delivered;
        }
        report(&driver);
      }
      driver.Stop();
      return delivered;
    } catch (const DeviceError& e) {
      ++failures;
      ++failed_attempts;
      last_error = e.what();
      char line[128];
      std::snprintf(line, sizeof(line), "; attempt %d failed, retrying in %.2f s", failures,
                    backoff_s);
      if (max_attempts > 0 && failures >= max_attempts) {
        log(std::string("aslam-rplidar: ") + e.what() + "; giving up after " +
            std::to_string(failures) + " attempts");
        return delivered;
      }
      log(std::string("aslam-rplidar: ") + e.what() + line);
    }
    // Sleep the backoff in small steps so a stop request is honoured promptly.
    const int64_t wake = HostClockUtime() + static_cast<int64_t>(backoff_s * 1e6);
    while (!stop && HostClockUtime() < wake) {
      report(nullptr);
      SleepS(0.02);
    }
    backoff_s = std::min(backoff_s * 2.0, options.reconnect_backoff_max_s);
  }
  return delivered;
}

}  // namespace aslam
