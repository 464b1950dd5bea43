#pragma once

// Hokuyo SCIP 2.0 ("Communication Protocol Specification For SCIP2.0", Hokuyo
// C-42-03320B, and the URG series protocol document it extends): pure encoding
// and decoding, no I/O.
//
// A command is a line: a 2-letter code, parameters, an optional ";tag" and LF.
// A response is: the echo of the command line, a status line (2 characters and
// their sum), data lines (payload and its sum), and an empty line. A sum is
// (sum of the payload's bytes) & 0x3F + 0x30. Numbers in data are sent 6 bits
// per character, each character being the value + 0x30, 2, 3 or 4 characters
// long, high bits first; scan data are cut into lines of 64 characters.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace aslam::scip {

// A response that parsed but does not carry what the protocol promises
// (missing PP keys, a scan of the wrong length, an unexpected status).
class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr char kLineFeed = '\n';
inline constexpr int kDataLineChars = 64;  // scan data are cut into lines this long
inline constexpr int kTimestampChars = 4;  // timestamps: 4 characters, 24 bits of ms
inline constexpr uint32_t kTimestampModulo = 1u << 24;
inline constexpr std::size_t kMaxLineChars = 256;  // longer without a LF: not SCIP

// The sum character of `payload`: (sum of its bytes) & 0x3F, plus 0x30.
char Checksum(std::string_view payload);

// `value` in `num_chars` characters (2, 3 or 4); throws std::invalid_argument if it does not fit.
std::string EncodeValue(uint32_t value, int num_chars);
// The value of 1 to 4 encoded characters; nullopt if a character is outside 0x30..0x6F.
std::optional<uint32_t> DecodeValue(std::string_view chars);

// ---- Commands (each a complete line, LF-terminated) ----

std::string VersionCommand();     // VV: vendor, product, firmware, protocol, serial
std::string ParametersCommand();  // PP: model and geometry
std::string StateCommand();       // II: laser, motor speed, mode, bit rate, time, state
std::string LaserOnCommand();     // BM
std::string QuitCommand();        // QT: stops scanning, laser off
std::string ResetCommand();       // RS: QT, and settings back to their defaults
std::string RebootCommand();      // RB: sent twice within 1 s it reboots the sensor
std::string Scip2Command();       // "SCIP2.0": a URG-04LX booted in SCIP 1.1 switches to 2.0
// TM0 enters time-adjust mode (laser off), TM1 asks the time, TM2 leaves it.
std::string TimeCommand(int control_code);

// 3 characters per range (MD/GD, up to 262143 mm) or 2 (MS/GS, up to 4095 mm).
enum class RangeEncoding { kThreeChar, kTwoChar };
int CharsPerValue(RangeEncoding encoding);

struct ScanRequest {
  int start_step = 0;
  int end_step = 0;
  int cluster_count = 1;  // adjacent steps merged into one value (the nearest), 1..99
  int scan_interval = 0;  // MD/MS: skip this many scans between those sent, 0..9
  int num_scans = 0;      // MD/MS: 0 = until QT, else 1..99
  RangeEncoding encoding = RangeEncoding::kThreeChar;
  std::string tag;  // optional ";tag" echoed back: up to 16 of [A-Za-z0-9 ._+@]
};
// MD/MS: continuous scanning. Throws std::invalid_argument for out-of-range fields.
std::string ContinuousScanCommand(const ScanRequest& request);
// GD/GS: the latest scan, once (laser must be on: BM).
std::string SingleScanCommand(const ScanRequest& request);

// ---- Responses ----

struct Response {
  std::string echo;    // the command line as echoed, without LF
  std::string status;  // "00", "99", "0E", ...; a SCIP 1.1 device answers one character ("E")
  // Data lines without their sum character ("DMIN:20;", "1Dh", a block of 64 characters).
  std::vector<std::string> lines;

  std::string command_code() const { return echo.substr(0, 2); }
  bool is_scip11_status() const { return status.size() == 1; }
};

// What the stream parser threw away, by cause.
struct ParserStats {
  int64_t responses = 0;        // complete, well-formed responses handed out
  int64_t checksum_errors = 0;  // responses dropped because a sum did not match
  int64_t partial_packets = 0;  // responses cut short (a reset, an unplug, lost bytes)
  int64_t garbage_bytes = 0;    // bytes outside any response (noise, a wrong bit rate)
};

// Turns arbitrary chunks of bytes into complete responses. It knows the length of
// scan data from the echoed MD/MS/GD/GS parameters, so a scan cut short is seen as
// soon as the next response starts, and it resynchronises on the next line that
// looks like an echo. Never throws on bad input: it counts.
class ResponseParser {
 public:
  // Appends every response completed by these bytes to `out`.
  void Feed(const uint8_t* data, std::size_t size, std::vector<Response>* out);
  void Feed(std::string_view bytes, std::vector<Response>* out);
  // The device went quiet mid-response (the caller's read timed out) or was reopened:
  // forgets the partial response (counted) and any partial line.
  void DropPartial();
  const ParserStats& stats() const { return stats_; }
  // Whether a response has started and not yet ended.
  bool in_response() const { return state_ != State::kEcho || !line_.empty(); }

 private:
  enum class State { kEcho, kStatus, kScanTimestamp, kScanData, kData, kEnd, kSkipToEnd };
  void OnLine(const std::string& line, std::vector<Response>* out);
  void StartScanData();
  void FinishResponse(std::vector<Response>* out);
  void AbandonResponse(int64_t* counter);

  State state_ = State::kEcho;
  std::string line_;
  Response current_;
  std::size_t scan_chars_expected_ = 0;  // data characters still due in a scan response
  std::size_t skipped_lines_ = 0;        // lines of a response being dropped
  ParserStats stats_;
};

// Whether `line` could be the echo of a SCIP 2.0 command (two capitals, printable).
bool LooksLikeEcho(std::string_view line);

// The meaning of `status` in answer to `command_code`, from the specification
// ("04: End Step is out of range"); "" for 00 (and 99 for MD/MS).
std::string StatusMeaning(std::string_view command_code, std::string_view status);
// Whether `status` is success for `command_code` (BM also accepts 02: laser already on).
bool IsSuccess(std::string_view command_code, std::string_view status);

// "KEY:value;" lines of VV, PP and II as a map (the value without the ';').
std::map<std::string, std::string> ParseKeyValues(const Response& response);

// PP: the sensor's model and geometry.
struct SensorParameters {
  std::string model;        // MODL
  int min_distance_mm = 0;  // DMIN: readings below are error codes
  int max_distance_mm = 0;  // DMAX
  int steps_per_turn = 0;   // ARES: steps in 360 degrees
  int first_step = 0;       // AMIN
  int last_step = 0;        // AMAX
  int front_step = 0;       // AFRT: the step straight ahead (angle 0)
  int scan_rpm = 0;         // SCAN: motor speed, one scan per turn

  double StepAngleRad(double step) const;  // counter-clockwise from the front
  double ScanPeriodS() const { return 60.0 / scan_rpm; }
};
// Throws ProtocolError naming the missing or invalid key.
SensorParameters ParseSensorParameters(const Response& pp_response);

// The timestamp and values of an MD/MS scan (status 99) or a GD/GS answer (status 00).
struct ScanData {
  std::string command_code;  // "MD", "MS", "GD", "GS"
  int start_step = 0;
  int end_step = 0;
  int cluster_count = 1;
  int remaining_scans = 0;    // MD/MS echo: scans still to come (0 = endless)
  uint32_t timestamp_ms = 0;  // sensor clock, 24 bits
  std::vector<uint32_t> values_mm;
};
// Whether the response carries scan data (MD/MS with 99, GD/GS with 00).
bool IsScanData(const Response& response);
// Throws ProtocolError if it is not scan data or the data do not match the echo.
ScanData ParseScanData(const Response& response);
// How many values a request yields: one per cluster of steps, the last maybe shorter.
int NumValues(int start_step, int end_step, int cluster_count);

// TM1: the sensor time in ms (24 bits). Throws ProtocolError.
uint32_t ParseTimeResponse(const Response& tm1_response);

}  // namespace aslam::scip
