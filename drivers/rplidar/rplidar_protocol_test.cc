// Expected bytes and values are worked out by hand from Slamtec's "RPLIDAR Interface
// Protocol and Application Notes" (request and answer layouts, the capsule angle formula)
// and, for ultra cabins, the rplidar_sdk the document refers to (sl_lidar_cmd.h: the cabin
// layout and the variable bit scale; sl_lidar_driver.cpp: predicts, escapes, angle offset).

#include "drivers/rplidar/rplidar_protocol.h"

#include <array>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

namespace aslam::rplidar {
namespace {

using Bytes = std::vector<uint8_t>;

std::vector<ScanSample> FeedAll(PacketFormat format, const Bytes& bytes,
                                ScanStreamParser* parser_out = nullptr) {
  ScanStreamParser parser(format);
  std::vector<ScanSample> samples;
  parser.Feed(bytes.data(), bytes.size(), &samples);
  if (parser_out) *parser_out = parser;
  return samples;
}

// A capsule with the given header bytes and cabin bytes (from byte 4 on), rest zero.
Bytes Capsule(uint8_t sync1, uint8_t sync2, uint8_t angle_low, uint8_t angle_high,
              const Bytes& cabins = {}) {
  Bytes c(kCapsuleSize, 0);
  c[0] = sync1;
  c[1] = sync2;
  c[2] = angle_low;
  c[3] = angle_high;
  for (std::size_t i = 0; i < cabins.size(); ++i) c[4 + i] = cabins[i];
  return c;
}

Bytes Join(std::initializer_list<Bytes> parts) {
  Bytes all;
  for (const Bytes& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

TEST(RplidarRequests, AreByteExact) {
  EXPECT_EQ(EncodeRequest(command::kStop), (Bytes{0xA5, 0x25}));
  EXPECT_EQ(EncodeRequest(command::kReset), (Bytes{0xA5, 0x40}));
  EXPECT_EQ(EncodeRequest(command::kScan), (Bytes{0xA5, 0x20}));
  EXPECT_EQ(EncodeRequest(command::kGetInfo), (Bytes{0xA5, 0x50}));
  EXPECT_EQ(EncodeRequest(command::kGetHealth), (Bytes{0xA5, 0x52}));
  EXPECT_EQ(EncodeRequest(command::kGetSampleRate), (Bytes{0xA5, 0x59}));
  // The document's legacy EXPRESS_SCAN: A5 82 05 00 00 00 00 00 22.
  EXPECT_EQ(EncodeExpressScanRequest(0), (Bytes{0xA5, 0x82, 0x05, 0, 0, 0, 0, 0, 0x22}));
  EXPECT_EQ(EncodeExpressScanRequest(1), (Bytes{0xA5, 0x82, 0x05, 1, 0, 0, 0, 0, 0x23}));
  // 600 rpm = 0x0258; checksum A5^A8^02^58^02 = 0x55.
  EXPECT_EQ(EncodeMotorSpeedRequest(600), (Bytes{0xA5, 0xA8, 0x02, 0x58, 0x02, 0x55}));
}

TEST(RplidarDescriptor, ParsesLengthModeAndType) {
  const Bytes scan = {0xA5, 0x5A, 0x05, 0x00, 0x00, 0x40, 0x81};
  const auto d = ParseDescriptor(scan.data());
  ASSERT_TRUE(d);
  EXPECT_EQ(d->length, 5u);
  EXPECT_EQ(d->send_mode, SendMode::kMultiple);
  EXPECT_EQ(d->data_type, 0x81);
  const Bytes info = {0xA5, 0x5A, 0x14, 0x00, 0x00, 0x00, 0x04};
  EXPECT_EQ(ParseDescriptor(info.data())->length, 20u);
  EXPECT_EQ(ParseDescriptor(info.data())->send_mode, SendMode::kSingle);
  const Bytes express = {0xA5, 0x5A, 0x54, 0x00, 0x00, 0x40, 0x82};
  EXPECT_EQ(ParseDescriptor(express.data())->length, 84u);
  // All 30 length bits, mode bits clear.
  const Bytes longest = {0xA5, 0x5A, 0xFF, 0xFF, 0xFF, 0x3F, 0x20};
  EXPECT_EQ(ParseDescriptor(longest.data())->length, 0x3FFFFFFFu);
  EXPECT_EQ(ParseDescriptor(longest.data())->send_mode, SendMode::kSingle);
  const Bytes no_sync = {0xA5, 0x5B, 0x05, 0x00, 0x00, 0x40, 0x81};
  EXPECT_FALSE(ParseDescriptor(no_sync.data()));
  EXPECT_EQ(EncodeDescriptor(*d), scan);
}

TEST(RplidarAnswers, DeviceInfoHealthAndSampleRate) {
  Bytes info = {0x18, 0x1D, 0x01, 0x07};
  for (int i = 0; i < 16; ++i) info.push_back(static_cast<uint8_t>(0xA0 + i));
  const auto parsed = ParseDeviceInfo(info.data(), info.size());
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->model, 0x18);
  EXPECT_EQ(parsed->FirmwareText(), "1.29");
  EXPECT_EQ(parsed->FirmwareNumber(), 0x011D);
  EXPECT_EQ(parsed->hardware, 7);
  EXPECT_EQ(parsed->SerialText(), "A0A1A2A3A4A5A6A7A8A9AAABACADAEAF");
  EXPECT_FALSE(ParseDeviceInfo(info.data(), 19));

  const Bytes warning = {0x01, 0x34, 0x12};
  EXPECT_EQ(ParseDeviceHealth(warning.data(), 3)->status, HealthStatus::kWarning);
  EXPECT_EQ(ParseDeviceHealth(warning.data(), 3)->error_code, 0x1234);
  const Bytes error = {0x02, 0x00, 0x80};
  EXPECT_EQ(ParseDeviceHealth(error.data(), 3)->status, HealthStatus::kError);
  const Bytes nonsense = {0x03, 0x00, 0x00};
  EXPECT_FALSE(ParseDeviceHealth(nonsense.data(), 3));

  const Bytes rate = {0xFC, 0x01, 0xFE, 0x00};  // 508 us and 254 us (an A1M8)
  EXPECT_EQ(ParseSampleRate(rate.data(), 4)->standard_us, 508);
  EXPECT_EQ(ParseSampleRate(rate.data(), 4)->express_us, 254);
}

TEST(RplidarModels, FromInfoByteAndNames) {
  EXPECT_EQ(ModelFromInfoByte(0x18), Model::kA1);
  EXPECT_EQ(ModelFromInfoByte(0x28), Model::kA2);
  EXPECT_EQ(ModelFromInfoByte(0x31), Model::kA3);
  EXPECT_EQ(ModelFromInfoByte(0x61), Model::kS1);
  EXPECT_EQ(ModelFromInfoByte(0x71), Model::kS2);
  EXPECT_EQ(ModelFromInfoByte(0x41), Model::kUnknown);
  EXPECT_EQ(ParseModelName("s2"), Model::kS2);
  EXPECT_FALSE(ParseModelName("A1"));
  EXPECT_EQ(DefaultsFor(Model::kA1).baud, 115200);
  EXPECT_EQ(DefaultsFor(Model::kA3).baud, 256000);
  EXPECT_EQ(DefaultsFor(Model::kS1).baud, 256000);
  EXPECT_EQ(DefaultsFor(Model::kS2).baud, 1000000);
  EXPECT_EQ(DefaultsFor(Model::kS1).motor, MotorControl::kSpeedCommand);
  EXPECT_EQ(DefaultsFor(Model::kA2).motor, MotorControl::kDtr);
}

// Node 1: S=1, quality 47, 90.0 deg (q6 5760), 1234.5 mm (q2 4938).
// Node 2: S=0, quality 10, 90.5 deg (q6 5792), no return.
const Bytes kNode1 = {0xBD, 0x01, 0x2D, 0x4A, 0x13};
const Bytes kNode2 = {0x2A, 0x41, 0x2D, 0x00, 0x00};

TEST(RplidarNodes, DecodeStartQualityAngleAndDistance) {
  const auto samples = FeedAll(PacketFormat::kStandardNodes, Join({kNode1, kNode2}));
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_TRUE(samples[0].start_of_revolution);
  EXPECT_EQ(samples[0].quality, 47);
  EXPECT_DOUBLE_EQ(samples[0].angle_cw_deg, 90.0);
  EXPECT_DOUBLE_EQ(samples[0].distance_m, 1.2345);
  EXPECT_EQ(samples[0].packet_end_offset, 5u);
  EXPECT_FALSE(samples[1].start_of_revolution);
  EXPECT_EQ(samples[1].quality, 10);
  EXPECT_DOUBLE_EQ(samples[1].angle_cw_deg, 90.5);
  EXPECT_EQ(samples[1].distance_m, 0.0);
  EXPECT_EQ(samples[1].slot, samples[0].slot + 1);
}

TEST(RplidarNodes, GarbageBeforeSyncIsSkipped) {
  // 0x00 has S == !S, 0x03 too; 0x01 0x00 fails the check bit.
  ScanStreamParser parser(PacketFormat::kStandardNodes);
  const Bytes bytes = Join({{0x00, 0x03, 0x01, 0x00}, kNode1, kNode2});
  std::vector<ScanSample> samples;
  parser.Feed(bytes.data(), bytes.size(), &samples);
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_DOUBLE_EQ(samples[0].angle_cw_deg, 90.0);
  EXPECT_DOUBLE_EQ(samples[1].angle_cw_deg, 90.5);
  EXPECT_EQ(parser.discarded_bytes(), 4);
  EXPECT_EQ(samples[0].packet_end_offset, 9u);
}

TEST(RplidarNodes, AngleAt360OrAboveIsRejected) {
  // q6 23040 = 360 deg: bytes 0x01 (check bit, low bits 0), 23040 >> 7 = 180 = 0xB4.
  const Bytes bad = {0xBD, 0x01, 0xB4, 0x00, 0x00};
  const auto samples = FeedAll(PacketFormat::kStandardNodes, bad);
  EXPECT_TRUE(samples.empty());
}

// Legacy capsule at 10 deg (q6 640 = 0x0280). Cabin 0: 1000 mm with dtheta +1.0 deg
// (q3 8 = 0b001000), 2000 mm with dtheta -0.5 deg (sign + q3 4 = 0b100100): words
// 0x0FA0 and 0x1F42, dtheta nibbles 0x48. Checksum (bytes 2..83) 0x38 -> A8 53.
const Bytes kCapsuleAt10 = Capsule(0xA8, 0x53, 0x80, 0x02, {0xA0, 0x0F, 0x42, 0x1F, 0x48});
// Empty capsules at 26 deg (q6 0x0680, checksum 0x86) and 42 deg (q6 0x0A80, checksum 0x8A).
const Bytes kCapsuleAt26 = Capsule(0xA6, 0x58, 0x80, 0x06);
const Bytes kCapsuleAt42 = Capsule(0xAA, 0x58, 0x80, 0x0A);

TEST(RplidarLegacyCapsules, DecodeWithTheNextCapsulesStartAngle) {
  ScanStreamParser parser(PacketFormat::kLegacyCapsules);
  std::vector<ScanSample> samples;
  parser.Feed(kCapsuleAt10.data(), kCapsuleAt10.size(), &samples);
  EXPECT_TRUE(samples.empty());  // needs the next start angle
  parser.Feed(kCapsuleAt26.data(), kCapsuleAt26.size(), &samples);
  ASSERT_EQ(samples.size(), 32u);
  // theta_k = 10 + 16 / 32 * k - dtheta_k
  EXPECT_DOUBLE_EQ(samples[0].angle_cw_deg, 9.0);
  EXPECT_DOUBLE_EQ(samples[0].distance_m, 1.0);
  EXPECT_DOUBLE_EQ(samples[1].angle_cw_deg, 11.0);
  EXPECT_DOUBLE_EQ(samples[1].distance_m, 2.0);
  EXPECT_DOUBLE_EQ(samples[31].angle_cw_deg, 25.5);
  EXPECT_EQ(samples[31].distance_m, 0.0);
  EXPECT_EQ(samples[0].samples_after_in_packet, 31u);
  EXPECT_EQ(samples[31].samples_after_in_packet, 0u);
  EXPECT_EQ(samples[0].packet_end_offset, 84u);
  EXPECT_EQ(samples[31].slot, 31u);
  EXPECT_EQ(parser.checksum_errors(), 0);
}

TEST(RplidarLegacyCapsules, CompensationSignBit) {
  EXPECT_DOUBLE_EQ(CabinAngleCompensationDeg(0b001000), 1.0);
  EXPECT_DOUBLE_EQ(CabinAngleCompensationDeg(0b100100), -0.5);
  EXPECT_DOUBLE_EQ(CabinAngleCompensationDeg(0b011111), 3.875);
  EXPECT_DOUBLE_EQ(CabinAngleCompensationDeg(0b111111), -3.875);
}

TEST(RplidarLegacyCapsules, WrapPast360StartsARevolution) {
  // 350 deg (q6 22400 = 0x5780, checksum 0xD7) then 6 deg (q6 384 = 0x0180, checksum 0x81).
  const Bytes at350 = Capsule(0xA7, 0x5D, 0x80, 0x57);
  const Bytes at6 = Capsule(0xA1, 0x58, 0x80, 0x01);
  const auto samples = FeedAll(PacketFormat::kLegacyCapsules, Join({at350, at6}));
  ASSERT_EQ(samples.size(), 32u);
  for (int k = 0; k < 32; ++k) {
    EXPECT_EQ(samples[k].start_of_revolution, k == 20) << k;  // 350 + 0.5 * 20 = 360
  }
  EXPECT_DOUBLE_EQ(samples[19].angle_cw_deg, 359.5);
  EXPECT_DOUBLE_EQ(samples[20].angle_cw_deg, 0.0);
}

TEST(RplidarLegacyCapsules, ChecksumErrorDropsOneCapsuleAndIsCounted) {
  Bytes corrupt = kCapsuleAt26;
  corrupt[40] = 0x01;  // checksum no longer matches
  ScanStreamParser parser(PacketFormat::kLegacyCapsules);
  const Bytes stream = Join({kCapsuleAt10, corrupt, kCapsuleAt42});
  std::vector<ScanSample> samples;
  parser.Feed(stream.data(), stream.size(), &samples);
  EXPECT_EQ(parser.checksum_errors(), 1);
  // The capsule at 10 deg is still decoded, spread over the span to 42 deg (32 deg / 64).
  ASSERT_EQ(samples.size(), 32u);
  EXPECT_DOUBLE_EQ(samples[0].angle_cw_deg, 9.0);
  EXPECT_DOUBLE_EQ(samples[1].angle_cw_deg, 11.0);
  EXPECT_DOUBLE_EQ(samples[31].angle_cw_deg, 25.5);
  // And the stream goes on: the 42 deg capsule follows the lost one in slot numbering.
  const Bytes at58 = Capsule(0xAE, 0x58, 0x80, 0x0E);  // q6 0x0E80, checksum 0x8E
  parser.Feed(at58.data(), at58.size(), &samples);
  ASSERT_EQ(samples.size(), 64u);
  EXPECT_DOUBLE_EQ(samples[32].angle_cw_deg, 42.0);
  EXPECT_EQ(samples[32].slot, 64u);
}

TEST(RplidarLegacyCapsules, GarbageBeforeSyncAndStartFlag) {
  // Garbage without a sync nibble pair; then a capsule with S = 1 (bit 15 of the angle word).
  const Bytes garbage = {0x12, 0x34, 0xA0, 0x00, 0x77};
  const Bytes flagged = Capsule(0xA8, 0x5B, 0x80, 0x82, {0xA0, 0x0F, 0x42, 0x1F, 0x48});
  ScanStreamParser parser(PacketFormat::kLegacyCapsules);
  const Bytes stream = Join({garbage, kCapsuleAt10, flagged, kCapsuleAt26});
  std::vector<ScanSample> samples;
  parser.Feed(stream.data(), stream.size(), &samples);
  EXPECT_EQ(parser.discarded_bytes(), 5);
  EXPECT_EQ(parser.checksum_errors(), 0);
  // S = 1 restarts the analysis: the capsule before it is dropped, the flagged one decoded.
  ASSERT_EQ(samples.size(), 32u);
  EXPECT_DOUBLE_EQ(samples[0].angle_cw_deg, 9.0);
  EXPECT_EQ(samples[0].packet_end_offset, 5u + 2 * 84);
}

// Dense capsule at 100 deg (q6 6400 = 0x1900): cabin 0 = 1500 mm (0x05DC), cabin 39 =
// 40000 mm (0x9C40); checksum 0x1C -> AC 51. Next at 104 deg (q6 0x1A00, checksum 0x1A).
TEST(RplidarDenseCapsules, DecodeFortyDistances) {
  Bytes cabins(80, 0);
  cabins[0] = 0xDC;
  cabins[1] = 0x05;
  cabins[78] = 0x40;
  cabins[79] = 0x9C;
  const Bytes at100 = Capsule(0xAC, 0x51, 0x00, 0x19, cabins);
  const Bytes at104 = Capsule(0xAA, 0x51, 0x00, 0x1A);
  ScanStreamParser parser(PacketFormat::kDenseCapsules);
  const auto samples = FeedAll(PacketFormat::kDenseCapsules, Join({at100, at104}), &parser);
  EXPECT_EQ(parser.checksum_errors(), 0);
  ASSERT_EQ(samples.size(), 40u);
  EXPECT_DOUBLE_EQ(samples[0].angle_cw_deg, 100.0);
  EXPECT_DOUBLE_EQ(samples[0].distance_m, 1.5);
  EXPECT_NEAR(samples[39].angle_cw_deg, 103.9, 1e-9);  // 100 + 4 / 40 * 39
  EXPECT_DOUBLE_EQ(samples[39].distance_m, 40.0);
  EXPECT_EQ(samples[20].distance_m, 0.0);
}

// Every split of the stream into two chunks decodes to the same samples as one chunk.
void ExpectSplitInvariant(PacketFormat format, const Bytes& stream) {
  const auto whole = FeedAll(format, stream);
  ASSERT_FALSE(whole.empty());
  for (std::size_t split = 0; split <= stream.size(); ++split) {
    ScanStreamParser parser(format);
    std::vector<ScanSample> samples;
    parser.Feed(stream.data(), split, &samples);
    parser.Feed(stream.data() + split, stream.size() - split, &samples);
    ASSERT_EQ(samples.size(), whole.size()) << "split at " << split;
    for (std::size_t i = 0; i < whole.size(); ++i) {
      EXPECT_EQ(samples[i].angle_cw_deg, whole[i].angle_cw_deg) << split << " " << i;
      EXPECT_EQ(samples[i].distance_m, whole[i].distance_m) << split << " " << i;
      EXPECT_EQ(samples[i].start_of_revolution, whole[i].start_of_revolution);
      EXPECT_EQ(samples[i].packet_end_offset, whole[i].packet_end_offset);
    }
  }
}

TEST(RplidarStreamParser, PartialPacketsSplitAtEveryBytePosition) {
  ExpectSplitInvariant(PacketFormat::kStandardNodes, Join({{0x00, 0x03}, kNode1, kNode2, kNode1}));
  ExpectSplitInvariant(PacketFormat::kLegacyCapsules,
                       Join({{0x11}, kCapsuleAt10, kCapsuleAt26, kCapsuleAt42}));
}

TEST(RplidarStreamParser, ByteByByteFeedingMatches) {
  const Bytes stream = Join({kCapsuleAt10, kCapsuleAt26, kCapsuleAt42});
  ScanStreamParser parser(PacketFormat::kLegacyCapsules);
  std::vector<ScanSample> samples;
  for (const uint8_t b : stream) parser.Feed(&b, 1, &samples);
  ASSERT_EQ(samples.size(), 64u);
  EXPECT_DOUBLE_EQ(samples[32].angle_cw_deg, 26.0);
}

// ---- Ultra capsules (answer type 0x84).

// An ultra cabin word: | predict2:10 | predict1:10 | major:12 |, predicts in two's complement.
uint32_t UltraCabin(uint32_t major, int predict1, int predict2) {
  return (major & 0xFFF) | ((static_cast<uint32_t>(predict1) & 0x3FF) << 12) |
         ((static_cast<uint32_t>(predict2) & 0x3FF) << 22);
}

// A 132-byte ultra capsule: sync nibbles over the XOR checksum of bytes 2..131, the angle
// word (S in bit 15), then 32 little-endian cabin words (missing ones zero).
Bytes UltraCapsule(uint16_t start_angle_q6, const std::vector<uint32_t>& cabins,
                   bool start_flag = false) {
  Bytes c(kUltraCapsuleSize, 0);
  const uint16_t word = static_cast<uint16_t>(start_angle_q6 | (start_flag ? 0x8000 : 0));
  c[2] = static_cast<uint8_t>(word & 0xFF);
  c[3] = static_cast<uint8_t>(word >> 8);
  for (std::size_t i = 0; i < cabins.size(); ++i) {
    for (int b = 0; b < 4; ++b) c[4 + 4 * i + b] = static_cast<uint8_t>(cabins[i] >> (8 * b));
  }
  uint8_t checksum = 0;
  for (std::size_t i = 2; i < c.size(); ++i) checksum ^= c[i];
  c[0] = static_cast<uint8_t>(0xA0 | (checksum & 0x0F));
  c[1] = static_cast<uint8_t>(0x50 | (checksum >> 4));
  return c;
}

TEST(RplidarUltraCabins, VarBitScaleBandEdges) {
  const auto expect = [](uint16_t raw, uint32_t mm, int shift) {
    const VarBitScaleValue v = DecodeVarBitScale(raw);
    EXPECT_EQ(v.distance_mm, mm) << raw;
    EXPECT_EQ(v.scale_shift, shift) << raw;
  };
  expect(0, 0, 0);
  expect(511, 511, 0);     // as is below 512
  expect(512, 512, 1);     // x2 from code 512 = 512 mm
  expect(1279, 2046, 1);   // 512 + 767 * 2
  expect(1280, 2048, 2);   // x4 from code 1280 = 2048 mm
  expect(1791, 4092, 2);   // 2048 + 511 * 4
  expect(1792, 4096, 3);   // x8 from code 1792 = 4096 mm
  expect(3327, 16376, 3);  // 4096 + 1535 * 8
  expect(3328, 16384, 4);  // x16 from code 3328 = 16384 mm
  expect(4095, 28656, 4);  // 16384 + 767 * 16: the farthest
}

TEST(RplidarUltraCabins, MajorAndPredictBranches) {
  using D = std::array<uint32_t, 3>;
  // Major 1000 = 512 + 488 * 2 = 1488 mm (x2); predict1 +5 * 2 on it; predict2 -3 * 1 on the
  // next major 300 (x1).
  EXPECT_EQ(DecodeUltraCabin(UltraCabin(1000, 5, -3), 300), (D{1488, 1498, 297}));
  // The escapes +511 and -512: no return.
  EXPECT_EQ(DecodeUltraCabin(UltraCabin(300, 511, -512), 0), (D{300, 0, 0}));
  // Major 0 (no return) with a next major 1500 = 2048 + 220 * 4 = 2928 (x4): both predicts
  // count from it, +7 * 4 and -1 * 4.
  EXPECT_EQ(DecodeUltraCabin(UltraCabin(0, 7, -1), 1500), (D{0, 2956, 2924}));
  // Major 0 and next major 0: predicts count from 0 mm in steps of 1.
  EXPECT_EQ(DecodeUltraCabin(UltraCabin(0, 3, 0), 0), (D{0, 3, 0}));
  // A negative sum (10 - 20) is no return; predict2 +5 on the next major 0.
  EXPECT_EQ(DecodeUltraCabin(UltraCabin(10, -20, 5), 0), (D{10, 0, 5}));
  // x16 band: 3328 + 100 -> 17984 mm, -1 * 16; predict2 +2 * 8 on 2000 = 4096 + 208 * 8 = 5760.
  EXPECT_EQ(DecodeUltraCabin(UltraCabin(3428, -1, 2), 2000), (D{17984, 17968, 5776}));
  EXPECT_EQ(DecodeUltraCabin(UltraCabin(4095, 3, -4), 600), (D{28656, 28704, 680}));
  // The next cabin was lost: what counts from its major is unknown.
  EXPECT_EQ(DecodeUltraCabin(UltraCabin(1500, -2, 1), std::nullopt), (D{2928, 2920, 0}));
  EXPECT_EQ(DecodeUltraCabin(UltraCabin(0, 7, 1), std::nullopt), (D{0, 0, 0}));
}

TEST(RplidarUltraCabins, AngleOffsetByDistance) {
  // Below 50 mm (and for no return): 7.5 deg.
  EXPECT_DOUBLE_EQ(UltraCabinAngleOffsetDeg(0), 7.5);
  EXPECT_DOUBLE_EQ(UltraCabinAngleOffsetDeg(49), 7.5);
  // 1000 mm: k = 98361 / 4000 = 24; 8 deg - 1536 / 65536 rad = 6.65713 deg.
  EXPECT_NEAR(UltraCabinAngleOffsetDeg(1000), 6.657130, 1e-6);
  // 297 mm: k = 98361 / 1188 = 82, 82^3 / 98304 = 5; 8 deg - (5248 + 5) / 65536 rad.
  EXPECT_NEAR(UltraCabinAngleOffsetDeg(297), 3.407490, 1e-6);
  // 50 mm: k = 491, 491^3 / 98304 = 1204; the formula goes below zero this close.
  EXPECT_NEAR(UltraCabinAngleOffsetDeg(50), -20.525493, 1e-6);
  // 28656 mm: k = 0, the full 8 deg.
  EXPECT_NEAR(UltraCabinAngleOffsetDeg(28656), 8.0, 1e-12);
}

// Ultra capsule at 100 deg (q6 6400), the next at 112 deg (q6 7168): 96 samples 0.125 deg apart.
const std::vector<uint32_t> kUltraCabinsAt100 = {
    UltraCabin(1000, 5, -3), UltraCabin(300, 511, -512), UltraCabin(0, 7, -1),
    UltraCabin(1500, -2, 1), UltraCabin(3428, -1, 2),    UltraCabin(2000, 0, 0),
    UltraCabin(10, -20, 5),  UltraCabin(0, 3, 0)};
Bytes UltraCapsuleAt100() {
  std::vector<uint32_t> cabins = kUltraCabinsAt100;
  cabins.resize(32, 0);
  cabins[30] = UltraCabin(0, 511, 511);
  cabins[31] = UltraCabin(4095, 3, -4);
  return UltraCapsule(6400, cabins);
}

TEST(RplidarUltraCapsules, DecodeNinetySixSamplesWithTheNextCapsule) {
  ScanStreamParser parser(PacketFormat::kUltraCapsules);
  std::vector<ScanSample> samples;
  const Bytes at100 = UltraCapsuleAt100();
  parser.Feed(at100.data(), at100.size(), &samples);
  EXPECT_TRUE(samples.empty());  // needs the next start angle and first major
  const Bytes at112 = UltraCapsule(7168, {UltraCabin(600, 0, 0)});
  parser.Feed(at112.data(), at112.size(), &samples);
  EXPECT_EQ(parser.checksum_errors(), 0);
  ASSERT_EQ(samples.size(), 96u);
  // theta_j = 100 + 12 / 96 * j - offset(distance_j).
  struct Expected {
    int j;
    uint32_t mm;
    double angle_deg;
  };
  const Expected expected[] = {
      {0, 1488, 92.895247},    // k 16: offset 7.104753
      {1, 1498, 93.020247},    // k 16
      {2, 297, 96.842510},     // k 82: offset 3.407490
      {3, 300, 96.911557},     // k 81: offset 3.463443
      {4, 0, 93.0},            // escape +511: offset 7.5
      {5, 0, 93.125},          // escape -512
      {6, 0, 93.25},           // major 0
      {7, 2956, 93.322623},    // k 8: offset 7.552377
      {8, 2924, 93.447623},    //
      {11, 18000, 93.430953},  // k 1: offset 7.944047
      {13, 17968, 93.680953},  //
      {14, 5776, 93.973812},   // k 4: offset 7.776188
      {19, 0, 94.875},         // 10 - 20 < 0: no return
      {20, 5, 95.0},           // under 50 mm: 7.5
      {22, 3, 95.25},          //
      {90, 0, 103.75},         // escapes of cabin 30
      {93, 28656, 103.625},    // k 0: offset 8
      {94, 28704, 103.75},     //
      {95, 680, 105.889305},   // predict2 on the next capsule's major 600 = 688; k 36
  };
  for (const Expected& e : expected) {
    EXPECT_DOUBLE_EQ(samples[e.j].distance_m, e.mm / 1000.0) << e.j;
    EXPECT_NEAR(samples[e.j].angle_cw_deg, e.angle_deg, 1e-6) << e.j;
  }
  EXPECT_EQ(samples[0].samples_after_in_packet, 95u);
  EXPECT_EQ(samples[95].samples_after_in_packet, 0u);
  EXPECT_EQ(samples[0].packet_end_offset, 132u);
  EXPECT_EQ(samples[0].packet_size, 132u);
  EXPECT_EQ(samples[95].slot, 95u);
}

TEST(RplidarUltraCapsules, ALostCapsuleLeavesOutOnlyTheSamplesThatNeedIt) {
  Bytes lost = UltraCapsule(7168, {UltraCabin(600, 0, 0)});
  lost[50] ^= 0x01;                                                 // checksum no longer matches
  const Bytes at124 = UltraCapsule(7936, {UltraCabin(700, 0, 0)});  // q6 7936 = 124 deg
  ScanStreamParser parser(PacketFormat::kUltraCapsules);
  const auto samples =
      FeedAll(PacketFormat::kUltraCapsules, Join({UltraCapsuleAt100(), lost, at124}), &parser);
  EXPECT_EQ(parser.checksum_errors(), 1);
  ASSERT_EQ(samples.size(), 96u);
  // Spread over the span to 124 deg (24 deg / 192): the same 0.125 deg steps.
  EXPECT_NEAR(samples[0].angle_cw_deg, 92.895247, 1e-6);
  EXPECT_DOUBLE_EQ(samples[94].distance_m, 28.704);
  EXPECT_EQ(samples[95].distance_m, 0.0);  // predicted from the lost capsule's first major
}

TEST(RplidarUltraCapsules, StartFlagWrapAndSplits) {
  EXPECT_EQ(PacketFormatForAnswer(answer::kUltraCapsuled), PacketFormat::kUltraCapsules);
  // 355 deg (q6 22720) then 7 deg (q6 448): 12 deg over 96 samples; raw 360 at sample 40.
  const Bytes at355 = UltraCapsule(22720, {}, /*start_flag=*/true);
  const Bytes at7 = UltraCapsule(448, {});
  const Bytes at19 = UltraCapsule(1216, {});
  const auto samples = FeedAll(PacketFormat::kUltraCapsules, Join({at355, at7, at19}));
  ASSERT_EQ(samples.size(), 192u);  // the 355 and 7 deg capsules
  for (int j = 0; j < 192; ++j) EXPECT_EQ(samples[j].start_of_revolution, j == 40) << j;
  // No return: raw - 7.5 deg.
  EXPECT_NEAR(samples[39].angle_cw_deg, 355.0 + 0.125 * 39 - 7.5, 1e-9);
  ExpectSplitInvariant(PacketFormat::kUltraCapsules,
                       Join({{0x11, 0xA5}, UltraCapsuleAt100(), at19, at355, at7}));
}

// ---- GET_LIDAR_CONF.

TEST(RplidarLidarConf, RequestBytes) {
  // A5 84 04 | type 0x70 LE | checksum A5^84^04^70 = 0x55.
  EXPECT_EQ(EncodeGetLidarConfRequest(lidar_conf::kScanModeCount),
            (Bytes{0xA5, 0x84, 0x04, 0x70, 0x00, 0x00, 0x00, 0x55}));
  EXPECT_EQ(EncodeGetLidarConfRequest(lidar_conf::kScanModeTypical),
            (Bytes{0xA5, 0x84, 0x04, 0x7C, 0x00, 0x00, 0x00, 0x59}));
  // Per-mode entries add the 16-bit mode id: A5^84^06^71^03 = 0x55.
  EXPECT_EQ(EncodeGetLidarConfRequest(lidar_conf::kScanModeUsPerSample, 3),
            (Bytes{0xA5, 0x84, 0x06, 0x71, 0x00, 0x00, 0x00, 0x03, 0x00, 0x55}));
}

TEST(RplidarLidarConf, AnswerValues) {
  // Descriptor A5 5A 08 00 00 00 20: single answer of 8 bytes.
  const Bytes descriptor = {0xA5, 0x5A, 0x08, 0x00, 0x00, 0x00, 0x20};
  EXPECT_EQ(ParseDescriptor(descriptor.data())->data_type, answer::kLidarConf);
  // US_PER_SAMPLE: 0x3E80 = 16000 in Q8 = 62.5 us.
  const Bytes us = {0x71, 0x00, 0x00, 0x00, 0x80, 0x3E, 0x00, 0x00};
  const auto us_value = ParseLidarConfValue(lidar_conf::kScanModeUsPerSample, us.data(), us.size());
  ASSERT_TRUE(us_value);
  EXPECT_DOUBLE_EQ(*LidarConfQ8(*us_value), 62.5);
  // MAX_DISTANCE: 25 m = 6400 = 0x1900 in Q8.
  const Bytes max = {0x74, 0x00, 0x00, 0x00, 0x00, 0x19, 0x00, 0x00};
  EXPECT_DOUBLE_EQ(*LidarConfQ8(*ParseLidarConfValue(0x74, max.data(), max.size())), 25.0);
  // COUNT (u16), ANS_TYPE (u8), NAME (text to the NUL).
  const Bytes count = {0x70, 0x00, 0x00, 0x00, 0x05, 0x00};
  EXPECT_EQ(*LidarConfUnsigned(*ParseLidarConfValue(0x70, count.data(), count.size()), 2), 5u);
  const Bytes type = {0x75, 0x00, 0x00, 0x00, 0x84};
  EXPECT_EQ(*LidarConfUnsigned(*ParseLidarConfValue(0x75, type.data(), type.size()), 1), 0x84u);
  const Bytes name = {0x7F, 0, 0, 0, 'S', 'e', 'n', 's', 'i', 't', 'i', 'v', 'i', 't', 'y', 0, 'x'};
  EXPECT_EQ(LidarConfText(*ParseLidarConfValue(0x7F, name.data(), name.size())), "Sensitivity");
  // Another entry's echo, or the type alone: no value.
  EXPECT_FALSE(ParseLidarConfValue(lidar_conf::kScanModeMaxDistance, us.data(), us.size()));
  EXPECT_FALSE(ParseLidarConfValue(0x70, count.data(), 4));
  EXPECT_FALSE(LidarConfQ8({0x80, 0x3E}));  // too short for a u32
  EXPECT_TRUE(ScanModeNameMatches("DenseBoost", "denseboost"));
  EXPECT_TRUE(ScanModeNameMatches("Sensitivity", "sensitivity"));
  EXPECT_FALSE(ScanModeNameMatches("Boost", "denseboost"));
  EXPECT_FALSE(ScanModeNameMatches("", ""));
}

}  // namespace
}  // namespace aslam::rplidar
