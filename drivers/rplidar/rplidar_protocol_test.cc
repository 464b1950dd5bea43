// Expected bytes and values are worked out by hand from Slamtec's "RPLIDAR Interface
// Protocol and Application Notes" (request and answer layouts, the capsule angle formula).

#include "drivers/rplidar/rplidar_protocol.h"

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

}  // namespace
}  // namespace aslam::rplidar
