#pragma once

// The Slamtec RPLIDAR driver over a ByteStream (a serial port, or a pseudo-terminal in
// tests): the connect sequence, the motor, SCAN or EXPRESS_SCAN, and whole revolutions
// binned into LidarScans. No LCM here (rplidar_lcm.h publishes).

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/config.h"
#include "common/pose2d.h"
#include "common/sensor_types.h"
#include "drivers/io/byte_stream.h"
#include "drivers/io/device_clock.h"
#include "drivers/io/driver_status.h"
#include "drivers/rplidar/rplidar_protocol.h"

namespace aslam {

// The `rplidar:` config section; flags of aslam-rplidar override port, baud, model, scan_mode.
struct RplidarOptions {
  std::string port = "/dev/rplidar";  // the udev link of the README
  int baud = 0;                       // 0 = the model's (115200 when model is auto)
  std::string model = "auto";         // a1, a2, a3, s1, s2, or auto (from GET_INFO)
  // standard (SCAN), express (legacy EXPRESS_SCAN), auto (the device's typical mode where it
  // lists its modes, else the model's), or a listed mode's name: boost, sensitivity, ...
  std::string scan_mode = "auto";
  int beams_per_revolution = 0;  // 0 = samples per revolution at the nominal scan rate
  double range_min_m = 0.0;      // 0 = the model's
  double range_max_m = 0.0;      // 0 = the model's
  int motor_rpm = 600;           // S1/S2 MOTOR_SPEED_CTRL speed (600 rpm = 10 Hz)
  double reconnect_backoff_initial_s = 0.5;
  double reconnect_backoff_max_s = 8.0;
  double reset_wait_s = 2.0;        // after RESET before talking again (an S1 needs 2 s)
  double response_timeout_s = 1.0;  // per answer to a request
  double stall_timeout_s = 1.0;     // scanning without a sample this long: restart the scan
  // The lidar in the base frame: the robot section's lidar_mount (LoadRplidarOptionsFromFile).
  Pose2d sensor_pose;
};

// Reads and validates the section (errors name file, key and value).
RplidarOptions LoadRplidarOptions(const ConfigReader& section);
// "" = defaults.
RplidarOptions LoadRplidarOptionsFromFile(const std::string& file);
// Checks values set in code or by flags; throws std::invalid_argument saying what is wrong.
void ValidateRplidarOptions(const RplidarOptions& options);
// The baud rate to open the port at: options.baud, else the model's default.
int ResolvedBaud(const RplidarOptions& options);

// What the connect sequence learned.
struct RplidarConnection {
  rplidar::DeviceInfo info;
  rplidar::Model model = rplidar::Model::kUnknown;
  rplidar::DeviceHealth health;
  rplidar::SampleRate sample_rate;
  // GET_LIDAR_CONF's scan modes (empty when not asked or not answered) and the typical one.
  std::vector<rplidar::ScanMode> scan_modes;
  std::optional<uint16_t> typical_scan_mode;
  std::string scan_mode_name;  // the mode scanning: a listed name, or standard/express
  rplidar::PacketFormat format = rplidar::PacketFormat::kStandardNodes;
  double sample_period_s = 0.0;
  int beams_per_revolution = 0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
};

struct RplidarStats {
  int64_t revolutions = 0;          // published
  int64_t dropped_revolutions = 0;  // incomplete (after a resync, a restart, garbage)
  int64_t checksum_errors = 0;
  int64_t discarded_bytes = 0;
  int64_t restarts = 0;  // scans restarted after a stall (e.g. the device reset itself)
};

class RplidarDriver {
 public:
  // Sets the DTR line; returns false where the port has none (a pseudo-terminal).
  using SetDtr = std::function<bool(bool asserted)>;
  using Log = std::function<void(const std::string&)>;

  // `baud` is what the port runs at (for the transfer-time correction of time stamps).
  // `log` gets one line per notable event (default: stderr).
  RplidarDriver(ByteStream& stream, RplidarOptions options, int baud, SetDtr set_dtr = {},
                Log log = {});

  // STOP, flush, GET_INFO, GET_HEALTH (RESET on an error, then give up if it stays),
  // GET_SAMPLERATE, GET_LIDAR_CONF (scan modes, A-series 1.24+), motor on, SCAN or
  // EXPRESS_SCAN in the chosen mode. Throws DeviceError naming the port.
  void Start();
  // Reads for at most `timeout_ms` and appends finished revolutions to *scans. Restarts a
  // scan that stalled (a device reset); throws DeviceError when the device is gone.
  void Poll(int timeout_ms, std::vector<LidarScan>* scans);
  // STOP and motor off, best effort: never throws.
  void Stop() noexcept;

  const RplidarConnection& connection() const { return connection_; }
  RplidarStats stats() const;
  // DRIVER_STATUS: the lidar's sample clock (samples x sample period) against the host's.
  DriverStatus driver_status() const;

 private:
  struct RevolutionSample {
    double angle_cw_deg;
    double distance_m;
    uint64_t slot;
    int64_t measured_utime;  // host-clock estimate from the bytes' arrival
  };
  struct ChunkArrival {
    uint64_t end_offset;  // parser stream offset just past the chunk
    int64_t host_utime;
  };

  [[noreturn]] void Fail(const std::string& what) const;
  void Send(const std::vector<uint8_t>& request);
  // Reads what arrives within timeout_ms into rx_; returns the byte count.
  std::size_t ReadIntoBuffer(int timeout_ms);
  // Sends `request`, waits for a descriptor of `data_type` and its `min_length` data bytes
  // (single answers) for at most timeout_s (0 = response_timeout_s).
  std::optional<std::vector<uint8_t>> Request(const std::vector<uint8_t>& request,
                                              uint8_t data_type, std::size_t min_length,
                                              std::size_t* noise_bytes, double timeout_s = 0.0);
  std::optional<std::vector<uint8_t>> Request(uint8_t command, uint8_t data_type,
                                              std::size_t min_length, std::size_t* noise_bytes);
  // One GET_LIDAR_CONF value; nullopt without a valid answer.
  std::optional<std::vector<uint8_t>> GetLidarConf(uint32_t type,
                                                   std::optional<uint16_t> scan_mode_id,
                                                   double timeout_s);
  // Fills connection_.scan_modes and typical_scan_mode; leaves them empty when the device
  // does not answer (old firmware) or answers wrong.
  void ListScanModes();
  std::optional<rplidar::ResponseDescriptor> WaitDescriptor(double timeout_s,
                                                            std::size_t* noise_bytes);
  void StopAndFlush();
  void ResetDevice();
  void Connect();
  void MotorOn();
  void StartStream();
  void Handle(const std::vector<rplidar::ScanSample>& samples, std::vector<LidarScan>* scans);
  int64_t ArrivalUtime(uint64_t offset) const;
  void FinishRevolution(std::vector<LidarScan>* scans);

  ByteStream& stream_;
  RplidarOptions options_;
  int baud_;
  SetDtr set_dtr_;
  Log log_;
  RplidarConnection connection_;
  std::vector<uint8_t> rx_;  // received, not yet consumed by a request or the parser
  std::optional<rplidar::ScanStreamParser> parser_;
  std::deque<ChunkArrival> arrivals_;
  std::vector<RevolutionSample> revolution_;
  bool in_revolution_ = false;
  int64_t last_sample_utime_ = 0;
  int64_t seq_ = 0;
  RplidarStats stats_;
  DeviceClock sample_clock_;
  RateCounter revolutions_;
  int64_t parser_checksum_errors_base_ = 0;
  int64_t parser_discarded_base_ = 0;
};

// Opens options.port at the resolved baud as a SerialPort, runs the driver and calls
// on_scan per revolution until `stop`; on a DeviceError (unplug, no answer) closes the
// port and retries with exponential backoff, logging each attempt once. Returns after
// `max_attempts` failed attempts in a row (0 = never gives up) or when `stop` is set;
// returns the number of revolutions delivered.
// on_status, when given, gets the driver's DRIVER_STATUS about once a second, connected or
// not (reconnects counts the failed attempts).
int64_t RunRplidarLoop(const RplidarOptions& options, const std::atomic<bool>& stop,
                       const std::function<void(const LidarScan&)>& on_scan,
                       const RplidarDriver::Log& log = {}, int max_attempts = 0,
                       const std::function<void(const DriverStatus&)>& on_status = {});

}  // namespace aslam
