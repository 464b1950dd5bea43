#include "drivers/hokuyo/scip_protocol.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace aslam::scip {
namespace {

constexpr std::size_t kMaxEchoChars = 40;          // longest command: 15 + ";" + 16-char tag
constexpr std::size_t kMaxDataLinesPerReply = 64;  // VV/PP/II have under 10; scans are counted
constexpr int kMaxClusterCount = 99;

bool IsTagCharacter(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == ' ' ||
         c == '.' || c == '_' || c == '+' || c == '@';
}

void CheckRange(const char* what, int value, int min, int max) {
  if (value < min || value > max) {
    throw std::invalid_argument(std::string("SCIP command: ") + what + " " + std::to_string(value) +
                                " is outside " + std::to_string(min) + ".." + std::to_string(max));
  }
}

std::string TagSuffix(const std::string& tag) {
  if (tag.empty()) return "";
  if (tag.size() > 16) throw std::invalid_argument("SCIP command: tag '" + tag + "' is over 16");
  for (char c : tag) {
    if (!IsTagCharacter(c)) {
      throw std::invalid_argument("SCIP command: tag '" + tag + "' has a character SCIP refuses");
    }
  }
  return ";" + tag;
}

std::string Digits(int value, int width) {
  char buffer[16];
  std::snprintf(buffer, sizeof(buffer), "%0*d", width, value);
  return buffer;
}

std::string ScanCommand(char kind, const ScanRequest& r, bool continuous) {
  CheckRange("start step", r.start_step, 0, 9999);
  CheckRange("end step", r.end_step, r.start_step, 9999);
  CheckRange("cluster count", r.cluster_count, 0, kMaxClusterCount);
  std::string line{kind, r.encoding == RangeEncoding::kTwoChar ? 'S' : 'D'};
  line += Digits(r.start_step, 4) + Digits(r.end_step, 4) + Digits(r.cluster_count, 2);
  if (continuous) {
    CheckRange("scan interval", r.scan_interval, 0, 9);
    CheckRange("number of scans", r.num_scans, 0, 99);
    line += Digits(r.scan_interval, 1) + Digits(r.num_scans, 2);
  }
  return line + TagSuffix(r.tag) + kLineFeed;
}

// Parses `count` decimal digits at `pos`; nullopt if any is not a digit.
std::optional<int> ParseDigits(std::string_view text, std::size_t pos, std::size_t count) {
  if (pos + count > text.size()) return std::nullopt;
  int value = 0;
  for (std::size_t i = pos; i < pos + count; ++i) {
    if (text[i] < '0' || text[i] > '9') return std::nullopt;
    value = value * 10 + (text[i] - '0');
  }
  return value;
}

struct ScanEcho {
  std::string code;
  int start_step = 0;
  int end_step = 0;
  int cluster_count = 1;
  int remaining_scans = 0;
  RangeEncoding encoding = RangeEncoding::kThreeChar;
};

// The parameters of an MD/MS/GD/GS echo; nullopt for anything else.
std::optional<ScanEcho> ParseScanEcho(std::string_view echo) {
  if (echo.size() < 12 || (echo[0] != 'M' && echo[0] != 'G') ||
      (echo[1] != 'D' && echo[1] != 'S')) {
    return std::nullopt;
  }
  const bool continuous = echo[0] == 'M';
  const std::size_t params_end = continuous ? 15 : 12;
  if (echo.size() < params_end || (echo.size() > params_end && echo[params_end] != ';')) {
    return std::nullopt;
  }
  const auto start = ParseDigits(echo, 2, 4);
  const auto end = ParseDigits(echo, 6, 4);
  const auto cluster = ParseDigits(echo, 10, 2);
  if (!start || !end || !cluster || *end < *start) return std::nullopt;
  ScanEcho parsed;
  parsed.code = std::string(echo.substr(0, 2));
  parsed.start_step = *start;
  parsed.end_step = *end;
  parsed.cluster_count = *cluster;
  parsed.encoding = echo[1] == 'S' ? RangeEncoding::kTwoChar : RangeEncoding::kThreeChar;
  if (continuous) {
    const auto remaining = ParseDigits(echo, 13, 2);
    if (!remaining || !ParseDigits(echo, 12, 1)) return std::nullopt;
    parsed.remaining_scans = *remaining;
  }
  return parsed;
}

bool ScanDataStatus(std::string_view code, std::string_view status) {
  return (code[0] == 'M' && status == "99") || (code[0] == 'G' && status == "00");
}

// A data line's sum covers the payload; VV/PP/II lines end "...;" + sum and the
// document's examples exclude the ';' (DMIN:20;4) while some firmware include it.
bool DataLineSumMatches(std::string_view payload, char sum) {
  if (Checksum(payload) == sum) return true;
  return !payload.empty() && payload.back() == ';' &&
         Checksum(payload.substr(0, payload.size() - 1)) == sum;
}

std::string InRange(int status, int low, int high, const char* meaning) {
  return status >= low && status <= high ? meaning : "";
}

}  // namespace

char Checksum(std::string_view payload) {
  unsigned sum = 0;
  for (char c : payload) sum += static_cast<uint8_t>(c);
  return static_cast<char>((sum & 0x3F) + 0x30);
}

std::string EncodeValue(uint32_t value, int num_chars) {
  if (num_chars < 1 || num_chars > 4 || (num_chars < 4 && value >= (1u << (6 * num_chars))) ||
      value >= (1u << 24)) {
    throw std::invalid_argument("SCIP: " + std::to_string(value) + " does not fit in " +
                                std::to_string(num_chars) + " characters");
  }
  std::string chars(static_cast<std::size_t>(num_chars), '0');
  for (int i = num_chars - 1; i >= 0; --i) {
    chars[static_cast<std::size_t>(i)] = static_cast<char>((value & 0x3F) + 0x30);
    value >>= 6;
  }
  return chars;
}

std::optional<uint32_t> DecodeValue(std::string_view chars) {
  if (chars.empty() || chars.size() > 4) return std::nullopt;
  uint32_t value = 0;
  for (char c : chars) {
    const int digit = static_cast<uint8_t>(c) - 0x30;
    if (digit < 0 || digit > 0x3F) return std::nullopt;
    value = (value << 6) | static_cast<uint32_t>(digit);
  }
  return value;
}

std::string VersionCommand() { return "VV\n"; }
std::string ParametersCommand() { return "PP\n"; }
std::string StateCommand() { return "II\n"; }
std::string LaserOnCommand() { return "BM\n"; }
std::string QuitCommand() { return "QT\n"; }
std::string ResetCommand() { return "RS\n"; }
std::string RebootCommand() { return "RB\n"; }
std::string Scip2Command() { return "SCIP2.0\n"; }

std::string TimeCommand(int control_code) {
  CheckRange("TM control code", control_code, 0, 2);
  return "TM" + std::to_string(control_code) + kLineFeed;
}

int CharsPerValue(RangeEncoding encoding) { return encoding == RangeEncoding::kTwoChar ? 2 : 3; }

std::string ContinuousScanCommand(const ScanRequest& request) {
  return ScanCommand('M', request, true);
}

std::string SingleScanCommand(const ScanRequest& request) {
  return ScanCommand('G', request, false);
}

int NumValues(int start_step, int end_step, int cluster_count) {
  const int cluster = cluster_count < 1 ? 1 : cluster_count;  // 00 means no clustering
  return (end_step - start_step + cluster) / cluster;
}

bool LooksLikeEcho(std::string_view line) {
  if (line.size() < 2 || line.size() > kMaxEchoChars) return false;
  if (line[0] < 'A' || line[0] > 'Z' || line[1] < 'A' || line[1] > 'Z') return false;
  for (char c : line) {
    if (c < 0x20 || c > 0x7E) return false;
  }
  return true;
}

// ---- ResponseParser ----

void ResponseParser::Feed(std::string_view bytes, std::vector<Response>* out) {
  Feed(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), out);
}

void ResponseParser::Feed(const uint8_t* data, std::size_t size, std::vector<Response>* out) {
  for (std::size_t i = 0; i < size; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == kLineFeed) {
      const std::string line = std::move(line_);
      line_.clear();
      OnLine(line, out);
      continue;
    }
    line_.push_back(c);
    if (line_.size() > kMaxLineChars) {
      // No SCIP line is this long: noise or a wrong bit rate.
      if (state_ != State::kEcho) AbandonResponse(&stats_.partial_packets);
      stats_.garbage_bytes += static_cast<int64_t>(line_.size());
      line_.clear();
    }
  }
}

void ResponseParser::DropPartial() {
  if (state_ != State::kEcho) {
    AbandonResponse(&stats_.partial_packets);
  } else if (!line_.empty()) {
    stats_.garbage_bytes += static_cast<int64_t>(line_.size());
  }
  line_.clear();
}

void ResponseParser::AbandonResponse(int64_t* counter) {
  ++*counter;
  current_ = Response{};
  scan_chars_expected_ = 0;
  skipped_lines_ = 0;
  state_ = State::kEcho;
}

void ResponseParser::FinishResponse(std::vector<Response>* out) {
  ++stats_.responses;
  out->push_back(std::move(current_));
  current_ = Response{};
  skipped_lines_ = 0;
  state_ = State::kEcho;
}

void ResponseParser::StartScanData() {
  const auto echo = ParseScanEcho(current_.echo);
  const int values = NumValues(echo->start_step, echo->end_step, echo->cluster_count);
  scan_chars_expected_ = static_cast<std::size_t>(values * CharsPerValue(echo->encoding));
  state_ = State::kScanTimestamp;
}

void ResponseParser::OnLine(const std::string& line, std::vector<Response>* out) {
  switch (state_) {
    case State::kEcho:
      if (LooksLikeEcho(line)) {
        current_ = Response{};
        current_.echo = line;
        state_ = State::kStatus;
      } else {
        stats_.garbage_bytes += static_cast<int64_t>(line.size() + 1);
      }
      return;

    case State::kStatus:
      if (line.size() == 3 && Checksum(std::string_view(line).substr(0, 2)) == line[2]) {
        current_.status = line.substr(0, 2);
        const auto echo = ParseScanEcho(current_.echo);
        if (echo && ScanDataStatus(echo->code, current_.status)) {
          StartScanData();
        } else {
          state_ = State::kData;
        }
      } else if (line.size() == 3) {
        state_ = State::kSkipToEnd;  // a status with a wrong sum: drop the whole response
      } else if (line.size() == 1 && line[0] >= 0x21 && line[0] <= 0x7E) {
        current_.status = line;  // SCIP 1.1: one character, no sum
        state_ = State::kData;
      } else {
        // The echo was cut short or was noise: this line may start the next response.
        AbandonResponse(&stats_.partial_packets);
        if (!line.empty()) OnLine(line, out);
      }
      return;

    case State::kScanTimestamp:
      if (line.size() == kTimestampChars + 1) {
        const std::string payload = line.substr(0, kTimestampChars);
        if (Checksum(payload) != line.back()) {
          state_ = State::kSkipToEnd;
          return;
        }
        current_.lines.push_back(payload);
        state_ = State::kScanData;
      } else {
        AbandonResponse(&stats_.partial_packets);
        if (!line.empty()) OnLine(line, out);
      }
      return;

    case State::kScanData: {
      const std::size_t chars =
          std::min<std::size_t>(scan_chars_expected_, static_cast<std::size_t>(kDataLineChars));
      if (line.size() != chars + 1) {
        AbandonResponse(&stats_.partial_packets);
        if (!line.empty()) OnLine(line, out);
        return;
      }
      const std::string payload = line.substr(0, chars);
      if (Checksum(payload) != line.back()) {
        state_ = State::kSkipToEnd;
        return;
      }
      current_.lines.push_back(payload);
      scan_chars_expected_ -= chars;
      if (scan_chars_expected_ == 0) state_ = State::kEnd;
      return;
    }

    case State::kEnd:
      if (line.empty()) {
        FinishResponse(out);
      } else {
        AbandonResponse(&stats_.partial_packets);  // more data than the echo announced
        OnLine(line, out);
      }
      return;

    case State::kData:
      if (line.empty()) {
        FinishResponse(out);
        return;
      }
      if (current_.lines.size() >= kMaxDataLinesPerReply) {
        stats_.garbage_bytes += static_cast<int64_t>(line.size() + 1);
        AbandonResponse(&stats_.partial_packets);
        return;
      }
      if (current_.is_scip11_status()) {
        current_.lines.push_back(line);  // SCIP 1.1 lines carry no sum
        return;
      }
      if (line.size() < 2 ||
          !DataLineSumMatches(std::string_view(line).substr(0, line.size() - 1), line.back())) {
        state_ = State::kSkipToEnd;
        return;
      }
      current_.lines.push_back(line.substr(0, line.size() - 1));
      return;

    case State::kSkipToEnd:
      if (line.empty()) {
        AbandonResponse(&stats_.checksum_errors);
      } else if (++skipped_lines_ > kMaxDataLinesPerReply) {
        AbandonResponse(&stats_.checksum_errors);  // no end in sight: resynchronise
      }
      return;
  }
}

// ---- Statuses ----

std::string StatusMeaning(std::string_view code, std::string_view status) {
  if (status.size() == 1) return "the sensor answers in SCIP 1.1 (send SCIP2.0 first)";
  if (status.size() != 2) return "malformed status";
  // Section 9, "Response to Invalid Commands": the same for every command.
  if (status == "0A") return "unable to create transmission data or reply internally";
  if (status == "0B") return "buffer shortage, or a command repeated that is already processed";
  if (status == "0C") return "command with insufficient parameters (1)";
  if (status == "0D") return "undefined command (1)";
  if (status == "0E") return "undefined command (2), or the sensor is in time-adjust mode (TM0)";
  if (status == "0F") return "command with insufficient parameters (2)";
  if (status == "0G") return "string characters in the command exceed 16 letters";
  if (status == "0H") return "string characters have invalid letters";
  if (status == "0I") return "the sensor is in firmware update mode (send RS and restart it)";
  const auto number = ParseDigits(status, 0, 2);
  if (!number) return "unknown status";
  const int n = *number;
  if (n == 0) return "";
  if (code == "MD" || code == "MS" || code == "GD" || code == "GS") {
    if (n == 99 && code[0] == 'M') return "";
    switch (n) {
      case 1: return "Starting Step has non-numeric value";
      case 2: return "End Step has non-numeric value";
      case 3: return "Cluster Count has non-numeric value";
      case 4: return "End Step is out of range";
      case 5: return "End Step is smaller than Starting Step";
      case 6: return "Scan Interval has non-numeric value";
      case 7: return "Number of Scan has non-numeric value";
      case 10: return "laser is off (send BM first)";
      case 98: return "resumption of process after confirming normal laser operation";
      default: break;
    }
    std::string meaning = InRange(n, 21, 49, "processing stopped to verify an error");
    if (meaning.empty()) {
      meaning = InRange(n, 50, 97, "hardware trouble (such as laser or motor malfunction)");
    }
    if (!meaning.empty()) return meaning;
  } else if (code == "BM") {
    if (n == 1) return "unable to control the laser: laser malfunction";
    if (n == 2) return "laser is already switched on";
  } else if (code == "TM") {
    if (n == 1) return "invalid control code";
    if (n == 2) return "adjust mode on received while adjust mode is already on";
    if (n == 3) return "adjust mode off received while adjust mode is already off";
    if (n == 4) return "adjust mode is off when the time was requested";
  } else if (code == "RB") {
    if (n == 1) return "first RB accepted: send RB again within 1 s to reboot";
  }
  return "error status " + std::string(status) + " (not in the SCIP 2.0 document)";
}

bool IsSuccess(std::string_view code, std::string_view status) {
  if (status == "00") return true;
  if (code == "BM" && status == "02") return true;
  return false;
}

// ---- VV / PP / II / TM ----

std::map<std::string, std::string> ParseKeyValues(const Response& response) {
  std::map<std::string, std::string> values;
  for (const std::string& line : response.lines) {
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos || colon == 0) continue;
    std::string value = line.substr(colon + 1);
    if (!value.empty() && value.back() == ';') value.pop_back();
    values[line.substr(0, colon)] = value;
  }
  return values;
}

double SensorParameters::StepAngleRad(double step) const {
  return (step - front_step) * 2.0 * M_PI / steps_per_turn;
}

SensorParameters ParseSensorParameters(const Response& pp) {
  if (pp.status != "00") {
    throw ProtocolError("PP answered status " + pp.status + ": " + StatusMeaning("PP", pp.status));
  }
  const auto values = ParseKeyValues(pp);
  auto integer = [&](const char* key) {
    const auto found = values.find(key);
    if (found == values.end()) throw ProtocolError(std::string("PP answer has no ") + key);
    const auto parsed = ParseDigits(found->second, 0, found->second.size());
    if (found->second.empty() || found->second.size() > 9 || !parsed) {
      throw ProtocolError(std::string("PP ") + key + " '" + found->second + "' is not a number");
    }
    return *parsed;
  };
  SensorParameters p;
  const auto model = values.find("MODL");
  p.model = model == values.end() ? "" : model->second;
  p.min_distance_mm = integer("DMIN");
  p.max_distance_mm = integer("DMAX");
  p.steps_per_turn = integer("ARES");
  p.first_step = integer("AMIN");
  p.last_step = integer("AMAX");
  p.front_step = integer("AFRT");
  p.scan_rpm = integer("SCAN");
  if (p.steps_per_turn <= 0) throw ProtocolError("PP ARES must be > 0");
  if (p.first_step > p.last_step) throw ProtocolError("PP AMIN is above AMAX");
  if (p.max_distance_mm <= p.min_distance_mm) throw ProtocolError("PP DMAX is not above DMIN");
  if (p.scan_rpm <= 0) throw ProtocolError("PP SCAN (rpm) must be > 0");
  return p;
}

bool IsScanData(const Response& response) {
  const auto echo = ParseScanEcho(response.echo);
  return echo && ScanDataStatus(echo->code, response.status);
}

ScanData ParseScanData(const Response& response) {
  const auto echo = ParseScanEcho(response.echo);
  if (!echo || !ScanDataStatus(echo->code, response.status)) {
    throw ProtocolError("'" + response.echo + "' with status " + response.status +
                        " carries no scan data");
  }
  if (response.lines.empty() || response.lines[0].size() != kTimestampChars) {
    throw ProtocolError("scan '" + response.echo + "' has no timestamp");
  }
  ScanData scan;
  scan.command_code = echo->code;
  scan.start_step = echo->start_step;
  scan.end_step = echo->end_step;
  scan.cluster_count = echo->cluster_count < 1 ? 1 : echo->cluster_count;
  scan.remaining_scans = echo->remaining_scans;
  scan.timestamp_ms = *DecodeValue(response.lines[0]);
  std::string data;
  for (std::size_t i = 1; i < response.lines.size(); ++i) data += response.lines[i];
  const int chars = CharsPerValue(echo->encoding);
  const int count = NumValues(echo->start_step, echo->end_step, echo->cluster_count);
  if (data.size() != static_cast<std::size_t>(count * chars)) {
    throw ProtocolError("scan '" + response.echo + "' has " + std::to_string(data.size()) +
                        " data characters, expected " + std::to_string(count * chars));
  }
  scan.values_mm.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const auto value = DecodeValue(std::string_view(data).substr(i * chars, chars));
    if (!value) throw ProtocolError("scan '" + response.echo + "' has a character outside SCIP");
    scan.values_mm.push_back(*value);
  }
  return scan;
}

uint32_t ParseTimeResponse(const Response& response) {
  if (response.status != "00") {
    throw ProtocolError("TM1 answered status " + response.status + ": " +
                        StatusMeaning("TM", response.status));
  }
  if (response.lines.empty() || response.lines[0].size() != kTimestampChars) {
    throw ProtocolError("TM1 answer has no 4-character time");
  }
  const auto value = DecodeValue(response.lines[0]);
  if (!value) throw ProtocolError("TM1 time has a character outside SCIP");
  return *value;
}

}  // namespace aslam::scip
