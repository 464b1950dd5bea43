#pragma once

// The Hokuyo driver: SCIP 2.0 over a ByteStream (USB serial for the URG-04LX,
// TCP for the UST-10LX/20LX), from the connect sequence to LidarScans stamped
// with the host clock.
//
// HokuyoSession is one connection: Connect() (QT, SCIP 1.1 -> 2.0 switch, VV, PP,
// II), SyncTime() (TM0, TM1 round trips, TM2), Start() (MD, or BM for GD polling),
// then ReadScan(). HokuyoDriver runs sessions for ever: it opens the device,
// reconnects with exponential backoff on any DeviceError, and never throws.

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/config.h"
#include "common/sensor_types.h"
#include "drivers/hokuyo/scip_protocol.h"
#include "drivers/io/byte_stream.h"
#include "drivers/io/device_clock.h"

namespace aslam {

enum class HokuyoModel { kAuto, kUrg04lx, kUst10lx, kUst20lx };
// "auto", "urg04lx", "ust10lx", "ust20lx"; nullopt for anything else.
std::optional<HokuyoModel> ParseHokuyoModel(const std::string& name);
std::string HokuyoModelName(HokuyoModel model);

struct HokuyoOptions {
  // Serial (URG-04LX-UG01, USB CDC-ACM): the port; the baud is set although USB ignores it.
  std::string port;
  int baud = 115200;
  // Ethernet (UST-10LX/20LX): the sensor's address and port.
  std::string host;
  int tcp_port = 10940;
  // Which sensor to expect; auto takes PP's MODL. Picks the default transport when neither
  // port nor host is given: /dev/ttyACM0 for the URG-04LX, 192.168.0.10 for the USTs.
  HokuyoModel model = HokuyoModel::kAuto;
  int start_step = -1;               // first step to measure; -1 = AMIN
  int end_step = -1;                 // last step; -1 = AMAX
  int cluster_count = 1;             // steps merged into one beam (the sensor sends the nearest)
  bool two_char_encoding = false;    // MS/GS: ranges only up to 4.095 m, a third less data
  bool poll_single_scans = false;    // GD/GS polling instead of MD/MS streaming
  int time_sync_round_trips = 10;    // TM1 round trips; the shortest sets the clock offset
  double response_timeout_s = 1.0;   // for one command's answer
  double scan_timeout_s = 1.0;       // no scan for this long: reconnect
  double reconnect_backoff_s = 0.5;  // first wait before reconnecting, doubling each failure
  double reconnect_backoff_max_s = 8.0;
  double connect_timeout_s = 3.0;  // TCP connect
  Pose2d sensor_pose;              // the lidar in the base frame: the robot section's lidar_mount

  bool uses_tcp() const { return !host.empty(); }
  std::string device_name() const;  // "/dev/ttyACM0" or "192.168.0.10:10940"
};

// The `hokuyo:` section; throws ConfigError naming file, key and value.
HokuyoOptions LoadHokuyoOptions(const ConfigReader& section);
// The file's `hokuyo:` section ("" = defaults) with its robot section's lidar_mount.
HokuyoOptions LoadHokuyoOptionsFromFile(const std::string& file);
// Fills the default transport from the model and checks the result; throws ConfigError.
void ResolveHokuyoTransport(HokuyoOptions* options);

// Sensor clock (24-bit ms, wrapping every 4.66 h) to host clock (HostClockUtime, us).
class SensorClockMapper {
 public:
  // One TM1 round trip: host time before sending, the sensor's answer, host time after.
  struct Sample {
    int64_t host_send_utime = 0;
    uint32_t sensor_ms = 0;
    int64_t host_receive_utime = 0;
  };
  // Uses the sample with the shortest round trip: its midpoint is the sensor time's host time.
  void Sync(const std::vector<Sample>& samples);
  bool synced() const { return synced_; }
  // The host time of a sensor timestamp, unwrapping the 24 bits against the last one seen.
  int64_t ToHostUtime(uint32_t sensor_ms);
  // A scan's beam 0 cannot be measured after the scan arrived: if the mapping says so
  // (the sensor clock runs fast), pull the offset back. Returns the corrected time.
  int64_t ClampToReceipt(int64_t mapped_utime, int64_t receive_utime);
  double best_round_trip_s() const { return best_round_trip_us_ * 1e-6; }
  int64_t offset_us() const { return offset_us_; }

 private:
  bool synced_ = false;
  int64_t offset_us_ = 0;  // host utime = offset + unwrapped sensor ms * 1000
  uint32_t last_raw_ms_ = 0;
  int64_t last_unwrapped_ms_ = 0;
  int64_t best_round_trip_us_ = 0;
};

// What the sensor said about itself at connect.
struct HokuyoInfo {
  std::map<std::string, std::string> version;  // VV: VEND, PROD, FIRM, PROT, SERI
  std::map<std::string, std::string> state;    // II: MODL, LASR, SCSP, MESM, SBPS, TIME, STAT
  scip::SensorParameters parameters;           // PP
  HokuyoModel model = HokuyoModel::kAuto;      // from MODL
  bool was_in_scip11 = false;                  // a URG-04LX that booted in SCIP 1.1
  std::vector<std::string> warnings;           // e.g. a model other than the configured one
};

struct HokuyoStats {
  int64_t scans = 0;
  int64_t scans_dropped = 0;   // cut short, bad sums or malformed: the stream went on
  int64_t error_statuses = 0;  // scan responses with an error status
  int64_t reconnects = 0;
  int64_t checksum_errors = 0;  // ScipParser counts, summed over sessions
  int64_t partial_packets = 0;
  int64_t garbage_bytes = 0;
  bool connected = false;        // a session is scanning
  double clock_offset_ms = 0.0;  // host time minus sensor time, from the TM round trips
  double clock_jitter_ms = 0.0;  // spread of the scans' arrivals around their mapped times
};

// Protocol trouble on a working byte stream (an error status, no answer, garbage):
// the driver retries on the same stream before reopening it.
class ScipSessionError : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

class HokuyoSession {
 public:
  HokuyoSession(ByteStream& stream, const HokuyoOptions& options);

  // QT (stops a scan left running), SCIP 1.1 -> 2.0 if needed, VV, PP, II.
  // Throws ScipSessionError naming the device and what it answered.
  const HokuyoInfo& Connect();
  // TM0, time_sync_round_trips x TM1, TM2.
  void SyncTime();
  // MD/MS (or BM for polling) over the configured steps.
  void Start();
  // The next scan, or nullopt if none arrived within timeout_ms (the stream goes on).
  // Throws ScipSessionError on an error status; DeviceError when the device is gone.
  std::optional<LidarScan> ReadScan(int timeout_ms);
  // QT; errors ignored (the device may be gone).
  void Stop();

  const HokuyoInfo& info() const { return info_; }
  const scip::ParserStats& parser_stats() const { return parser_.stats(); }
  int64_t scans_dropped() const { return scans_dropped_; }
  const SensorClockMapper& clock() const { return clock_; }
  // The scan command sent by Start(), e.g. "MD0044072501000\n".
  const std::string& scan_command() const { return scan_command_; }

 private:
  void Send(const std::string& command);
  // The answer to `command` (its echo), skipping other responses; nullopt on timeout.
  std::optional<scip::Response> Await(const std::string& command, int timeout_ms);
  // Await that throws ScipSessionError on timeout or a failure status.
  scip::Response Command(const std::string& command);
  std::optional<scip::Response> NextResponse(int64_t deadline_utime);
  void DiscardPendingInput(int quiet_ms);
  std::string NoAnswerMessage(const std::string& command) const;
  LidarScan ToLidarScan(const scip::ScanData& data, int64_t receive_utime);
  void CheckStepRange();

  ByteStream& stream_;
  HokuyoOptions options_;
  scip::ResponseParser parser_;
  std::deque<scip::Response> pending_;
  HokuyoInfo info_;
  SensorClockMapper clock_;
  scip::ScanRequest request_;
  std::string scan_command_;
  int64_t poll_sent_utime_ = 0;  // GD/GS polling: when the outstanding request went out
  bool poll_outstanding_ = false;
  int64_t scans_dropped_ = 0;
  int64_t bytes_received_ = 0;
  int64_t last_byte_utime_ = 0;  // when bytes last arrived: silence mid-response ends it
};

class HokuyoDriver {
 public:
  using StreamFactory = std::function<std::unique_ptr<ByteStream>()>;
  using ScanHandler = std::function<void(const LidarScan&)>;
  using LogHandler = std::function<void(const std::string&)>;

  // `open_stream` defaults to a SerialPort or TcpStream from the options.
  explicit HokuyoDriver(HokuyoOptions options, StreamFactory open_stream = nullptr);

  // Connects, scans and hands each scan to `on_scan` until `stop` is set; on any
  // DeviceError logs it, waits (backoff, doubling up to the maximum) and reconnects.
  // Never throws; `on_scan` exceptions are logged and the scan dropped.
  void Run(const std::atomic<bool>& stop, const ScanHandler& on_scan);

  void set_log(LogHandler log) { log_ = std::move(log); }
  // Thread-safe copies for monitoring.
  HokuyoStats stats() const;
  std::string last_error() const;
  std::optional<HokuyoInfo> info() const;

 private:
  void Log(const std::string& message);
  void RunSession(ByteStream& stream, const std::atomic<bool>& stop, const ScanHandler& on_scan);
  bool SleepUnlessStopped(double seconds, const std::atomic<bool>& stop);

  HokuyoOptions options_;
  StreamFactory open_stream_;
  LogHandler log_;
  mutable std::mutex mutex_;
  HokuyoStats stats_;
  DeviceClock arrivals_;  // the scans' mapped times against their arrivals, for the jitter
  std::string last_error_;
  std::optional<HokuyoInfo> info_;
  int64_t next_seq_ = 0;
};

}  // namespace aslam
