#pragma once

// Test support: a Hokuyo lidar speaking SCIP 2.0, written from Hokuyo's protocol
// document (C-42-03320B) without the driver's encoder or parser. It serves a
// URG-04LX over a pseudo-terminal or a UST-10LX over TCP on 127.0.0.1 (an
// ephemeral port) from its own thread, answers VV/PP/II/QT/RS/RB/BM/TM/MD/MS/GD/GS
// and SCIP2.0, streams scans of a range function at the model's rate (or faster:
// time_scale), keeps a 24-bit millisecond clock, and injects faults on request.
//
// Model parameters (PP), and where they come from:
//   URG-04LX: DMIN 20, DMAX 5600, ARES 1024, AMIN 44, AMAX 725, AFRT 384, SCAN 600 -
//     the PP example of the SCIP 2.0 document (C-42-03320B section 8.12) and Hokuyo's
//     urgnetwork SCIP pages; 683 steps 44..725 = 240 degrees, 100 ms per scan.
//   UST-10LX: DMIN 20, DMAX 30000, ARES 1440, AMIN 0, AMAX 1080, AFRT 540, SCAN 2400 -
//     not in a Hokuyo document found here: a UST-10LX's PP as logged from hardware by a
//     public driver, consistent with the UST-10LX data sheet (270 degrees in 0.25 degree
//     steps = 1081 steps, 25 ms per scan).

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "drivers/io/pseudo_terminal.h"

namespace aslam::testing {

enum class EmulatedHokuyo { kUrg04lx, kUst10lx };

struct HokuyoModelParameters {
  std::string model;  // PP MODL
  int dmin_mm, dmax_mm, ares, amin, amax, afrt, scan_rpm;
};
const HokuyoModelParameters& ParametersOf(EmulatedHokuyo model);

struct HokuyoEmulatorOptions {
  EmulatedHokuyo model = EmulatedHokuyo::kUrg04lx;
  // Scans come time_scale times faster than the model's rate; the sensor clock stays
  // real-time (1 ms per ms), as the driver's clock sync needs.
  double time_scale = 1.0;
  // The sensor clock at power-on (ms, 24 bits): just below 2^24 tests the wrap.
  uint32_t clock_start_ms = 0;
  // Range at a step's angle (rad, counter-clockwise from AFRT) in a scan; <= 0, under
  // DMIN or over DMAX is sent as error code 1. Default: 2 m everywhere.
  std::function<double(double angle_rad, int64_t scan_index)> range_m;
  // A URG-04LX whose firmware boots in SCIP 1.1 (answers "E" until SCIP2.0).
  bool boot_in_scip11 = false;
};

// One scan as sent: the test compares the driver's stamps and ranges with it.
struct EmulatedScan {
  int64_t scan_index = 0;
  uint32_t timestamp_ms = 0;     // sensor clock at the first requested step (24 bits)
  int64_t beam0_host_utime = 0;  // HostClockUtime() of that instant
  bool corrupted = false;        // sent with a bad sum (the driver must drop it)
};

class HokuyoEmulator {
 public:
  // A URG-04LX (or any model) behind a pseudo-terminal: open device_path() as a serial port.
  static std::unique_ptr<HokuyoEmulator> OnPseudoTerminal(HokuyoEmulatorOptions options);
  // A UST-10LX (or any model) listening on 127.0.0.1:tcp_port().
  static std::unique_ptr<HokuyoEmulator> OnTcp(HokuyoEmulatorOptions options);
  ~HokuyoEmulator();
  HokuyoEmulator(const HokuyoEmulator&) = delete;
  HokuyoEmulator& operator=(const HokuyoEmulator&) = delete;

  std::string device_path() const;  // the pseudo-terminal's slave ("" over TCP)
  int tcp_port() const { return tcp_port_; }

  // ---- Faults ----
  // Sends these bytes now, between responses.
  void InjectGarbage(const std::string& bytes);
  // The next scan goes out with one data line's sum wrong.
  void CorruptNextScanChecksum();
  // The next command with this code ("PP", "MD", ...) is answered with `status` only.
  void FailNextCommand(const std::string& code, const std::string& status);
  // The next scan is replaced by an error status (e.g. "50", hardware trouble) and
  // streaming stops, laser off.
  void InjectScanErrorStatus(const std::string& status);
  // The next scan is cut in half and the sensor reboots: clock from 0, laser off, idle,
  // back in SCIP 1.1 if it boots so.
  void ResetMidScan();
  // Answers nothing, but sends noise (like a device at another bit rate).
  void SetGarbageOnly(bool garbage_only);
  // Serial: the pseudo-terminal closes (a pulled USB cable). TCP: the connection closes.
  void Unplug();
  // Serial: a new pseudo-terminal, in the state of a power-on; returns its slave path.
  std::string Replug();

  // ---- Observations ----
  std::vector<std::string> received_commands() const;  // each line with its terminator
  std::vector<EmulatedScan> sent_scans() const;
  int64_t scans_sent() const;
  int tcp_connections() const;
  bool in_scip2() const;
  // The sensor clock now (ms, 24 bits).
  uint32_t SensorClockMs() const;

 private:
  explicit HokuyoEmulator(HokuyoEmulatorOptions options);
  void Loop();
  // Under mutex_, on the emulator thread:
  void Send(const std::string& bytes);
  void HandleLine(const std::string& line);
  void HandleScip2Command(const std::string& command, const std::string& echo);
  void StartScan(const std::string& command, const std::string& echo, bool continuous);
  void SendDueScans();
  std::string ScanData(const std::string& echo, int start, int end, int cluster, bool two_char,
                       int64_t scan_index, int64_t beam0_host_utime, bool corrupt);
  void PowerOn();
  uint32_t SensorMsAt(int64_t host_utime) const;
  double ScanPeriodUs() const;

  HokuyoEmulatorOptions options_;
  const HokuyoModelParameters params_;
  mutable std::mutex mutex_;
  std::atomic<bool> stop_{false};
  std::thread thread_;

  // Transport.
  std::unique_ptr<PseudoTerminal> pty_;
  int listen_fd_ = -1;
  int client_fd_ = -1;
  int tcp_port_ = 0;
  int tcp_connections_ = 0;

  // Sensor state.
  std::string input_line_;
  bool scip2_ = true;
  bool laser_on_ = false;
  bool time_adjust_mode_ = false;
  int64_t boot_utime_ = 0;
  uint32_t boot_clock_ms_ = 0;
  int rb_count_ = 0;
  // Streaming MD/MS.
  bool streaming_ = false;
  std::string stream_echo_prefix_;  // echo up to the remaining-scan count
  std::string stream_tag_;          // ";tag" or ""
  int stream_start_ = 0, stream_end_ = 0, stream_cluster_ = 1, stream_interval_ = 0;
  int stream_remaining_ = 0;
  bool stream_endless_ = true;  // MD/MS with 00 scans: until QT
  bool stream_two_char_ = false;
  int64_t next_scan_utime_ = 0;
  int64_t scan_index_ = 0;

  // Faults.
  std::string pending_garbage_;
  bool corrupt_next_scan_ = false;
  std::string fail_code_, fail_status_;
  std::string scan_error_status_;
  bool reset_mid_scan_ = false;
  bool garbage_only_ = false;
  int64_t next_noise_utime_ = 0;
  bool unplug_requested_ = false;  // Unplug/Replug: done by the thread, which polls the fds
  bool replug_requested_ = false;

  // Observations.
  std::vector<std::string> received_;
  std::vector<EmulatedScan> sent_;
};

}  // namespace aslam::testing
