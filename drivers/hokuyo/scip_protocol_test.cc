#include "drivers/hokuyo/scip_protocol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace aslam::scip {
namespace {

// A line and its sum as the sensor sends it (the sum is checked against the document below).
std::string WithSum(const std::string& payload) {
  unsigned sum = 0;
  for (char c : payload) sum += static_cast<uint8_t>(c);
  return payload + static_cast<char>((sum & 0x3F) + 0x30) + "\n";
}

// Three characters per value, high bits first, each + 0x30 (written out independently).
std::string Encode3(uint32_t v) {
  return {static_cast<char>(((v >> 12) & 0x3F) + 0x30), static_cast<char>(((v >> 6) & 0x3F) + 0x30),
          static_cast<char>((v & 0x3F) + 0x30)};
}

// Four characters: a 24-bit timestamp.
std::string Encode4(uint32_t v) { return Encode3(v >> 6).substr(0, 1) + Encode3(v & 0x3FFFF); }

// An MD scan response of `values` (3-character) from step 44, in 64-character lines.
std::string ScanResponse(const std::vector<uint32_t>& values, uint32_t timestamp_ms) {
  const int end = 44 + static_cast<int>(values.size()) - 1;
  char echo[32];
  std::snprintf(echo, sizeof(echo), "MD0044%04d01000", end);
  std::string data;
  for (uint32_t v : values) data += Encode3(v);
  std::string text = std::string(echo) + "\n" + WithSum("99");
  text += WithSum(Encode4(timestamp_ms));
  for (std::size_t i = 0; i < data.size(); i += 64) text += WithSum(data.substr(i, 64));
  return text + "\n";
}

std::vector<Response> FeedAll(ResponseParser& parser, const std::string& bytes) {
  std::vector<Response> out;
  parser.Feed(bytes, &out);
  return out;
}

TEST(ScipCommandTest, SimpleCommandsAreByteExact) {
  EXPECT_EQ(VersionCommand(), "VV\n");
  EXPECT_EQ(ParametersCommand(), "PP\n");
  EXPECT_EQ(StateCommand(), "II\n");
  EXPECT_EQ(LaserOnCommand(), "BM\n");
  EXPECT_EQ(QuitCommand(), "QT\n");
  EXPECT_EQ(ResetCommand(), "RS\n");
  EXPECT_EQ(RebootCommand(), "RB\n");
  EXPECT_EQ(Scip2Command(), "SCIP2.0\n");
  EXPECT_EQ(TimeCommand(0), "TM0\n");
  EXPECT_EQ(TimeCommand(1), "TM1\n");
  EXPECT_EQ(TimeCommand(2), "TM2\n");
  EXPECT_THROW(TimeCommand(3), std::invalid_argument);
}

TEST(ScipCommandTest, ScanCommandsAreByteExact) {
  ScanRequest urg_full;
  urg_full.start_step = 44;
  urg_full.end_step = 725;
  EXPECT_EQ(ContinuousScanCommand(urg_full), "MD0044072501000\n");
  EXPECT_EQ(SingleScanCommand(urg_full), "GD0044072501\n");

  // The document's example range, 10 to 750, in 2-character encoding with every field set.
  ScanRequest r;
  r.start_step = 10;
  r.end_step = 750;
  r.cluster_count = 3;
  r.scan_interval = 1;
  r.num_scans = 5;
  r.encoding = RangeEncoding::kTwoChar;
  r.tag = "abc";
  EXPECT_EQ(ContinuousScanCommand(r), "MS0010075003105;abc\n");
  EXPECT_EQ(SingleScanCommand(r), "GS0010075003;abc\n");
}

TEST(ScipCommandTest, ScanCommandsRejectFieldsScipCannotCarry) {
  ScanRequest r;
  r.start_step = 100;
  r.end_step = 99;
  EXPECT_THROW(ContinuousScanCommand(r), std::invalid_argument);
  r.end_step = 200;
  r.cluster_count = 100;
  EXPECT_THROW(ContinuousScanCommand(r), std::invalid_argument);
  r.cluster_count = 1;
  r.scan_interval = 10;
  EXPECT_THROW(ContinuousScanCommand(r), std::invalid_argument);
  r.scan_interval = 0;
  r.tag = "bad!";
  EXPECT_THROW(ContinuousScanCommand(r), std::invalid_argument);
  r.tag = std::string(17, 'a');
  EXPECT_THROW(ContinuousScanCommand(r), std::invalid_argument);
  r.tag = std::string(16, 'a');
  EXPECT_NO_THROW(ContinuousScanCommand(r));
}

TEST(ScipChecksumTest, MatchesTheDocumentsExamples) {
  // Status lines "00P", "99b", "02R", "0Ee" and the PP/VV/II examples of the
  // SCIP 2.0 document (C-42-03320B) and Hokuyo's urgnetwork SCIP pages.
  EXPECT_EQ(Checksum("00"), 'P');
  EXPECT_EQ(Checksum("99"), 'b');
  EXPECT_EQ(Checksum("02"), 'R');
  EXPECT_EQ(Checksum("0E"), 'e');
  EXPECT_EQ(Checksum("DMIN:20"), '4');
  EXPECT_EQ(Checksum("DMAX:5600"), '_');
  EXPECT_EQ(Checksum("ARES:1024"), '\\');
  EXPECT_EQ(Checksum("AMIN:44"), '7');
  EXPECT_EQ(Checksum("AMAX:725"), 'o');
  EXPECT_EQ(Checksum("AFRT:384"), '6');
  EXPECT_EQ(Checksum("SCAN:600"), 'e');
  EXPECT_EQ(Checksum("PROT:SCIP 2.0"), 'N');
  EXPECT_EQ(Checksum("SERI:H0614967"), 'V');
  EXPECT_EQ(Checksum("MODL:URG-04LX(Hokuyo Automatic Co.,Ltd.)"), 'N');
  EXPECT_EQ(Checksum("LASR:OFF"), '7');
}

TEST(ScipEncodingTest, DecodesHandComputedValues) {
  // 1234 = 010011 010010 -> 0x13+0x30 'C', 0x12+0x30 'B' (the document's 2-character example).
  EXPECT_EQ(DecodeValue("CB"), 1234u);
  // 5432 = 000001 010100 111000 -> '1', 'D', 'h' (the document's 3-character example).
  EXPECT_EQ(DecodeValue("1Dh"), 5432u);
  EXPECT_EQ(DecodeValue("0000"), 0u);
  EXPECT_EQ(DecodeValue("oooo"), 16777215u);  // 24 bits set: the last timestamp before the wrap
  EXPECT_EQ(DecodeValue("10"), 64u);
  EXPECT_EQ(DecodeValue("0o"), 63u);
  EXPECT_FALSE(DecodeValue("/0").has_value());  // 0x2F is below the alphabet
  EXPECT_FALSE(DecodeValue("0p").has_value());  // 0x70 is above it
  EXPECT_FALSE(DecodeValue("").has_value());
}

TEST(ScipEncodingTest, EncodesTheSameHandComputedValues) {
  EXPECT_EQ(EncodeValue(1234, 2), "CB");
  EXPECT_EQ(EncodeValue(5432, 3), "1Dh");
  EXPECT_EQ(EncodeValue(16777215, 4), "oooo");
  EXPECT_EQ(EncodeValue(4095, 2), "oo");
  EXPECT_THROW(EncodeValue(4096, 2), std::invalid_argument);
  EXPECT_THROW(EncodeValue(1u << 18, 3), std::invalid_argument);
}

TEST(ScipParserTest, ParsesThePpExampleOfTheDocument) {
  ResponseParser parser;
  const auto out = FeedAll(parser,
                           "PP\n00P\n"
                           "MODL:URG-04LX(Hokuyo Automatic Co.,Ltd.);N\n"
                           "DMIN:20;4\nDMAX:5600;_\nARES:1024;\\\nAMIN:44;7\nAMAX:725;o\n"
                           "AFRT:384;6\nSCAN:600;e\n\n");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].echo, "PP");
  EXPECT_EQ(out[0].status, "00");
  const SensorParameters p = ParseSensorParameters(out[0]);
  EXPECT_EQ(p.model, "URG-04LX(Hokuyo Automatic Co.,Ltd.)");
  EXPECT_EQ(p.min_distance_mm, 20);
  EXPECT_EQ(p.max_distance_mm, 5600);
  EXPECT_EQ(p.steps_per_turn, 1024);
  EXPECT_EQ(p.first_step, 44);
  EXPECT_EQ(p.last_step, 725);
  EXPECT_EQ(p.front_step, 384);
  EXPECT_EQ(p.scan_rpm, 600);
  EXPECT_DOUBLE_EQ(p.ScanPeriodS(), 0.1);
  // Step 384 is straight ahead; 128 steps of 1024 are a quarter turn, counter-clockwise.
  EXPECT_DOUBLE_EQ(p.StepAngleRad(384), 0.0);
  EXPECT_NEAR(p.StepAngleRad(640), M_PI / 2, 1e-12);
  EXPECT_NEAR(p.StepAngleRad(44), -340.0 / 1024 * 2 * M_PI, 1e-12);
  EXPECT_EQ(parser.stats().checksum_errors, 0);
}

TEST(ScipParserTest, AcceptsKeyValueSumsThatIncludeTheSemicolon) {
  // Some firmware sum "KEY:value;" rather than "KEY:value": both are accepted.
  ResponseParser parser;
  const auto out = FeedAll(parser, "VV\n00P\n" + WithSum("PROT:SCIP 2.0;") + "\n");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(ParseKeyValues(out[0]).at("PROT"), "SCIP 2.0");
}

TEST(ScipParserTest, PpWithoutAKeyIsAClearError) {
  ResponseParser parser;
  const auto out = FeedAll(parser, "PP\n00P\nDMIN:20;4\nDMAX:5600;_\n\n");
  ASSERT_EQ(out.size(), 1u);
  try {
    ParseSensorParameters(out[0]);
    FAIL() << "expected ProtocolError";
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("ARES"), std::string::npos) << e.what();
  }
}

TEST(ScipParserTest, ParsesVvKeyValues) {
  ResponseParser parser;
  const auto out = FeedAll(parser,
                           "VV\n00P\nVEND:Hokuyo Automatic Co.,Ltd.;[\n"
                           "PROT:SCIP 2.0;N\nSERI:H0614967;V\n\n");
  ASSERT_EQ(out.size(), 1u);
  const auto values = ParseKeyValues(out[0]);
  EXPECT_EQ(values.at("VEND"), "Hokuyo Automatic Co.,Ltd.");
  EXPECT_EQ(values.at("PROT"), "SCIP 2.0");
  EXPECT_EQ(values.at("SERI"), "H0614967");
}

TEST(ScipParserTest, MultiBlockScanDecodesEveryValue) {
  std::vector<uint32_t> values;
  for (int i = 0; i < 50; ++i) values.push_back(static_cast<uint32_t>(20 + i * 111));  // 150 chars
  const std::string text = ScanResponse(values, 0xABCDEF);
  ResponseParser parser;
  const auto out = FeedAll(parser, text);
  ASSERT_EQ(out.size(), 1u);
  ASSERT_EQ(out[0].lines.size(), 4u);  // timestamp, 64 + 64 + 22 characters
  EXPECT_EQ(out[0].lines[3].size(), 22u);
  ASSERT_TRUE(IsScanData(out[0]));
  const ScanData scan = ParseScanData(out[0]);
  EXPECT_EQ(scan.command_code, "MD");
  EXPECT_EQ(scan.start_step, 44);
  EXPECT_EQ(scan.end_step, 93);
  EXPECT_EQ(scan.timestamp_ms, 0xABCDEFu);
  EXPECT_EQ(scan.values_mm, values);
}

TEST(ScipParserTest, DataOfExactlyOneBlockEndsAfterItsSum) {
  // 64 characters exactly: one full block, then the empty line (no short last block).
  std::vector<uint32_t> values(64 / 2, 1000);
  std::string text = "MS0000003101000\n" + WithSum("99") + WithSum("0000");
  std::string data;
  for (uint32_t v : values)
    data += std::string{static_cast<char>((v >> 6) + 0x30)} + static_cast<char>((v & 0x3F) + 0x30);
  text += WithSum(data) + "\n";
  ResponseParser parser;
  const auto out = FeedAll(parser, text);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(ParseScanData(out[0]).values_mm, values);
}

TEST(ScipParserTest, ClusteredTwoCharacterGsScan) {
  // Steps 0..10 in clusters of 4: 3 values, the last cluster 3 steps wide.
  const std::string text =
      "GS0000001004\n" + WithSum("00") + WithSum("0001") + WithSum("CBCB0o") + "\n";
  ResponseParser parser;
  const auto out = FeedAll(parser, text);
  ASSERT_EQ(out.size(), 1u);
  const ScanData scan = ParseScanData(out[0]);
  EXPECT_EQ(scan.cluster_count, 4);
  EXPECT_EQ(scan.timestamp_ms, 1u);
  EXPECT_EQ(scan.values_mm, (std::vector<uint32_t>{1234, 1234, 63}));
}

TEST(ScipParserTest, ErrorStatusesComeThroughWithTheirMeaning) {
  ResponseParser parser;
  const auto out = FeedAll(parser, "MD0044080001000\n" + WithSum("04") + "\n" + "GD0044072501\n" +
                                       WithSum("10") + "\n" + "MD0044072501000\n" + WithSum("55") +
                                       "\n" + "XY\n" + WithSum("0E") + "\n");
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].status, "04");
  EXPECT_FALSE(IsScanData(out[0]));
  EXPECT_EQ(StatusMeaning("MD", "04"), "End Step is out of range");
  EXPECT_EQ(StatusMeaning("GD", out[1].status), "laser is off (send BM first)");
  EXPECT_NE(StatusMeaning("MD", out[2].status).find("hardware trouble"), std::string::npos);
  EXPECT_NE(StatusMeaning("XY", out[3].status).find("undefined command"), std::string::npos);
  EXPECT_EQ(StatusMeaning("MD", "99"), "");
  EXPECT_TRUE(IsSuccess("BM", "02"));
  EXPECT_FALSE(IsSuccess("MD", "04"));
  EXPECT_THROW(ParseScanData(out[0]), ProtocolError);
}

TEST(ScipParserTest, Scip11AnswerHasAOneCharacterStatus) {
  ResponseParser parser;
  const auto out = FeedAll(parser, "QT\nE\n\n");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].is_scip11_status());
  EXPECT_EQ(out[0].status, "E");
}

TEST(ScipParserTest, GarbageBeforeAResponseIsCountedAndSkipped) {
  ResponseParser parser;
  std::string noise = "\x01\xff\x7f noise\n\n~~~ 12\n";
  noise += std::string(300, 'x');  // a "line" longer than SCIP allows, without LF
  const auto out = FeedAll(parser, noise + "\nQT\n00P\n\n");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].echo, "QT");
  EXPECT_GE(parser.stats().garbage_bytes, 300);
  EXPECT_EQ(parser.stats().responses, 1);
}

TEST(ScipParserTest, ScanSplitAtEveryBytePositionParsesTheSame) {
  std::vector<uint32_t> values;
  for (int i = 0; i < 40; ++i) values.push_back(static_cast<uint32_t>(3000 - i * 50));
  const std::string text = ScanResponse(values, 77);
  for (std::size_t cut = 0; cut <= text.size(); ++cut) {
    ResponseParser parser;
    std::vector<Response> out;
    parser.Feed(text.substr(0, cut), &out);
    EXPECT_EQ(out.size(), cut == text.size() ? 1u : 0u) << "cut " << cut;
    parser.Feed(text.substr(cut), &out);
    ASSERT_EQ(out.size(), 1u) << "cut " << cut;
    EXPECT_EQ(ParseScanData(out[0]).values_mm, values) << "cut " << cut;
    EXPECT_EQ(parser.stats().partial_packets, 0) << "cut " << cut;
  }
}

TEST(ScipParserTest, ScanCutShortAtEveryPositionIsCountedAndTheNextParses) {
  std::vector<uint32_t> values(40, 1500);
  const std::string scan = ScanResponse(values, 5);
  const std::string next = ScanResponse(std::vector<uint32_t>(40, 2500), 6);
  // Cut anywhere after the echo's LF and before the last LF, then a quiet spell (the
  // driver's read times out: DropPartial) and the next scan: it must parse.
  for (std::size_t cut = scan.find('\n') + 1; cut + 1 < scan.size(); ++cut) {
    ResponseParser parser;
    std::vector<Response> out;
    parser.Feed(scan.substr(0, cut), &out);
    parser.DropPartial();
    parser.Feed(next, &out);
    ASSERT_EQ(out.size(), 1u) << "cut " << cut;
    EXPECT_EQ(ParseScanData(out[0]).timestamp_ms, 6u) << "cut " << cut;
    EXPECT_EQ(parser.stats().partial_packets, 1) << "cut " << cut;
  }
}

TEST(ScipParserTest, ScanCutAtALineEndResynchronisesOnTheNextEchoWithoutAPause) {
  const std::string scan = ScanResponse(std::vector<uint32_t>(40, 1500), 5);
  const std::string next = ScanResponse(std::vector<uint32_t>(40, 2500), 6);
  int cuts = 0;
  for (std::size_t cut = scan.find('\n') + 1; cut < scan.size(); cut = scan.find('\n', cut) + 1) {
    if (cut >= scan.size()) break;  // the whole scan: nothing cut
    ResponseParser parser;
    const auto out = FeedAll(parser, scan.substr(0, cut) + next);
    ASSERT_EQ(out.size(), 1u) << "cut " << cut;
    EXPECT_EQ(ParseScanData(out[0]).timestamp_ms, 6u) << "cut " << cut;
    EXPECT_EQ(parser.stats().partial_packets, 1) << "cut " << cut;
    ++cuts;
  }
  EXPECT_EQ(cuts, 5);  // after the echo, the status, the timestamp and each of 2 blocks
}

TEST(ScipParserTest, BadBlockSumDropsThatScanOnly) {
  std::vector<uint32_t> values(40, 1500);
  std::string bad = ScanResponse(values, 1);
  const std::size_t first_block_sum = bad.find('\n', bad.find('\n', bad.find('\n') + 1) + 1) + 65;
  ASSERT_EQ(bad[first_block_sum + 1], '\n');
  bad[first_block_sum] = bad[first_block_sum] == 'A' ? 'B' : 'A';
  ResponseParser parser;
  const auto out = FeedAll(parser, ScanResponse(values, 0) + bad + ScanResponse(values, 2));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(ParseScanData(out[0]).timestamp_ms, 0u);
  EXPECT_EQ(ParseScanData(out[1]).timestamp_ms, 2u);
  EXPECT_EQ(parser.stats().checksum_errors, 1);
  EXPECT_EQ(parser.stats().partial_packets, 0);
}

TEST(ScipParserTest, BadStatusSumDropsTheResponse) {
  ResponseParser parser;
  const auto out = FeedAll(parser, "QT\n00Q\n\nQT\n00P\n\n");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(parser.stats().checksum_errors, 1);
}

TEST(ScipParserTest, DropPartialForgetsAResponseInProgress) {
  ResponseParser parser;
  std::vector<Response> out;
  parser.Feed(std::string("VV\n00P\nVEND:Hokuyo Automatic Co.,Ltd.;[\n"), &out);
  EXPECT_TRUE(parser.in_response());
  parser.DropPartial();
  EXPECT_FALSE(parser.in_response());
  EXPECT_EQ(parser.stats().partial_packets, 1);
  parser.Feed(std::string("PROT:SCIP 2.0;N\n\nQT\n00P\n\n"), &out);
  ASSERT_EQ(out.size(), 1u);  // the orphaned VV tail is garbage, the QT answer parses
  EXPECT_EQ(out[0].echo, "QT");
}

TEST(ScipParserTest, TimeResponse) {
  ResponseParser parser;
  const auto out = FeedAll(parser, "TM1\n00P\n" + WithSum("1Dh0") + "\n");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(ParseTimeResponse(out[0]), (5432u << 6));
}

TEST(ScipParserTest, NumValuesCountsThePartialLastCluster) {
  EXPECT_EQ(NumValues(44, 725, 1), 682);
  EXPECT_EQ(NumValues(44, 725, 3), 228);
  EXPECT_EQ(NumValues(0, 1080, 1), 1081);
  EXPECT_EQ(NumValues(10, 10, 0), 1);
}

}  // namespace
}  // namespace aslam::scip
