// libFuzzer: arbitrary bytes from a serial or TCP device, as each driver's parser takes them:
// the first byte picks the device (Kobuki packets and feedback, an RPLIDAR scan stream in
// one of its four packet formats, SCIP 2.0 responses and what the Hokuyo driver parses out
// of them), the second the chunk size the bytes arrive in. Counted garbage is the expected
// answer; a scip::ProtocolError naming what is wrong is too. Nothing else may escape.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "drivers/hokuyo/scip_protocol.h"
#include "drivers/kobuki/kobuki_protocol.h"
#include "drivers/rplidar/rplidar_protocol.h"

namespace {

void FeedKobuki(const uint8_t* data, std::size_t size, std::size_t chunk) {
  aslam::kobuki::PacketParser parser;
  for (std::size_t at = 0; at < size; at += chunk) {
    std::vector<std::vector<uint8_t>> payloads;
    parser.Push(data + at, std::min(chunk, size - at), &payloads);
    for (const auto& payload : payloads) (void)aslam::kobuki::ParseFeedback(payload);
  }
}

void FeedRplidar(const uint8_t* data, std::size_t size, std::size_t chunk, uint8_t format) {
  using aslam::rplidar::PacketFormat;
  constexpr PacketFormat kFormats[] = {PacketFormat::kStandardNodes, PacketFormat::kLegacyCapsules,
                                       PacketFormat::kDenseCapsules, PacketFormat::kUltraCapsules};
  aslam::rplidar::ScanStreamParser parser(kFormats[format % 4]);
  std::vector<aslam::rplidar::ScanSample> samples;
  for (std::size_t at = 0; at < size; at += chunk) {
    parser.Feed(data + at, std::min(chunk, size - at), &samples);
  }
}

void FeedScip(const uint8_t* data, std::size_t size, std::size_t chunk) {
  namespace scip = aslam::scip;
  scip::ResponseParser parser;
  std::vector<scip::Response> responses;
  for (std::size_t at = 0; at < size; at += chunk) {
    parser.Feed(data + at, std::min(chunk, size - at), &responses);
  }
  for (const scip::Response& response : responses) {
    try {
      (void)scip::ParseKeyValues(response);
      if (scip::IsScanData(response)) (void)scip::ParseScanData(response);
      if (response.command_code() == "PP") (void)scip::ParseSensorParameters(response);
      if (response.command_code() == "TM") (void)scip::ParseTimeResponse(response);
    } catch (const scip::ProtocolError&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const uint8_t device = data[0];
  const std::size_t chunk = 1 + data[1] % 64;
  data += 2;
  size -= 2;
  switch (device % 3) {
    case 0: FeedKobuki(data, size, chunk); break;
    case 1: FeedRplidar(data, size, chunk, device / 3); break;
    default: FeedScip(data, size, chunk); break;
  }
  return 0;
}
