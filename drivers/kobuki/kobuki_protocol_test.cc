// The Kobuki protocol against bytes worked out by hand from the specification.

#include "drivers/kobuki/kobuki_protocol.h"

#include <gtest/gtest.h>

#include <cmath>

namespace aslam::kobuki {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes Concat(Bytes a, const Bytes& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

TEST(KobukiProtocol, BaseControlAndRequestExtraPacketsAreByteExact) {
  // Speed 100 mm/s = 0x0064, radius 0; checksum 0x06^0x01^0x04^0x64 = 0x67.
  EXPECT_EQ(EncodePacket(BaseControlSubPayload(100, 0)),
            (Bytes{0xAA, 0x55, 0x06, 0x01, 0x04, 0x64, 0x00, 0x00, 0x00, 0x67}));
  // Speed -1 = 0xFFFF, radius -300 = 0xFED4; checksum 0x06^0x01^0x04^0xFF^0xFF^0xD4^0xFE.
  EXPECT_EQ(EncodePacket(BaseControlSubPayload(-1, -300)),
            (Bytes{0xAA, 0x55, 0x06, 0x01, 0x04, 0xFF, 0xFF, 0xD4, 0xFE, 0x29}));
  // Hardware + firmware version + unique id = 0x0B; checksum 0x04^0x09^0x02^0x0B = 0x04.
  EXPECT_EQ(EncodePacket(RequestExtraSubPayload(0x0B)),
            (Bytes{0xAA, 0x55, 0x04, 0x09, 0x02, 0x0B, 0x00, 0x04}));
  EXPECT_THROW(EncodePacket({1, 0}), std::invalid_argument);
}

// Left and right wheel speeds (mm/s) the base drives for a Base Control, per the spec's table.
void WheelSpeeds(BaseControl c, double half_base_mm, double* left, double* right) {
  if (c.radius_mm == 0) {
    *left = *right = c.speed_mm_s;
  } else if (c.radius_mm == 1) {
    *left = -c.speed_mm_s;
    *right = c.speed_mm_s;
  } else {
    // speed is the outer wheel's; the inner one is at (R - b/2) / (R + b/2) of it.
    const double r = c.radius_mm;
    const double outer = c.speed_mm_s;
    const double inner = outer * (std::abs(r) - half_base_mm) / (std::abs(r) + half_base_mm);
    *left = r > 0 ? inner : outer;
    *right = r > 0 ? outer : inner;
  }
}

TEST(KobukiProtocol, TwistsBecomeTheSpecsSpeedAndRadius) {
  const double b = 0.230;
  EXPECT_EQ(BaseControlFromTwist(0.2, 0.0, b).speed_mm_s, 200);
  EXPECT_EQ(BaseControlFromTwist(0.2, 0.0, b).radius_mm, 0);
  // Pure rotation: w * b / 2 with radius 1, counter-clockwise positive.
  EXPECT_EQ(BaseControlFromTwist(0.0, 1.0, b).speed_mm_s, 115);
  EXPECT_EQ(BaseControlFromTwist(0.0, 1.0, b).radius_mm, 1);
  EXPECT_EQ(BaseControlFromTwist(0.0, -1.0, b).speed_mm_s, -115);
  // An arc of 400 mm to the left at 0.2 m/s: speed * (R + b/2) / R = 257.5 mm/s.
  EXPECT_EQ(BaseControlFromTwist(0.2, 0.5, b).radius_mm, 400);
  EXPECT_EQ(BaseControlFromTwist(0.2, 0.5, b).speed_mm_s, 258);
  // To the right: R = -400, speed * (R - b/2) / R, again the outer (left) wheel.
  EXPECT_EQ(BaseControlFromTwist(0.2, -0.5, b).radius_mm, -400);
  EXPECT_EQ(BaseControlFromTwist(0.2, -0.5, b).speed_mm_s, 258);
  // Wider than the field holds: straight.
  EXPECT_EQ(BaseControlFromTwist(0.3, 0.005, b).radius_mm, 0);
  EXPECT_EQ(BaseControlFromTwist(0.3, 0.005, b).speed_mm_s, 300);

  // Whatever the twist, the wheels the base drives reproduce it.
  for (double v : {-0.4, -0.1, 0.0, 0.05, 0.3, 0.5}) {
    for (double w : {-1.8, -0.7, -0.02, 0.0, 0.3, 1.2}) {
      double left = 0, right = 0;
      WheelSpeeds(BaseControlFromTwist(v, w, b), 115.0, &left, &right);
      const double v_back = 0.5 * (left + right) / 1000.0;
      const double w_back = (right - left) / 1000.0 / b;
      if (std::abs(w) > 0.01 || w == 0.0) {
        EXPECT_NEAR(v_back, v, 0.003) << v << " " << w;
        EXPECT_NEAR(w_back, w, 0.01) << v << " " << w;
      }
    }
  }
}

Bytes BasicSensorDataSubPayload() {
  return {0x01, 15,                 // id, length
          0x34, 0x12,               // timestamp 0x1234
          0x02, 0x01, 0x04,         // bumper central, right wheel dropped, left cliff
          0xFE, 0xFF, 0x10, 0x00,   // encoders 65534, 16
          0x9C, 0x64,               // PWM -100, 100
          0x01, 22,   163,  0x02};  // button 0, adapter charging, 16.3 V, right overcurrent
}

TEST(KobukiProtocol, FeedbackSubPayloadsAreParsedAndOthersSkipped) {
  const Bytes inertial = {0x04, 7, 0x28, 0x23, 0x9C, 0xFF, 0, 0, 0};  // 90.00°, -1.00°/s
  const Bytes docking_ir = {0x03, 3, 0, 0, 0};
  const Bytes hardware = {0x0A, 4, 4, 0, 1, 0};  // patch 4, minor 0, major 1
  const Bytes firmware = {0x0B, 4, 0, 2, 1, 0};  // 1.2.0
  const Bytes udid = {0x13, 12, 0x78, 0x56, 0x34, 0x12, 1, 0, 0, 0, 2, 0, 0, 0};
  const Bytes gp_input(18, 0);
  Bytes gpi = gp_input;
  gpi[0] = 0x10;
  gpi[1] = 16;
  const auto feedback = ParseFeedback(Concat(
      Concat(Concat(Concat(Concat(BasicSensorDataSubPayload(), docking_ir), inertial), hardware),
             Concat(firmware, udid)),
      gpi));
  ASSERT_TRUE(feedback.has_value());
  ASSERT_TRUE(feedback->basic.has_value());
  EXPECT_EQ(feedback->basic->timestamp_ms, 0x1234);
  EXPECT_EQ(feedback->basic->bumper, kBumperCentral);
  EXPECT_EQ(feedback->basic->wheel_drop, kWheelDropRight);
  EXPECT_EQ(feedback->basic->cliff, kCliffLeft);
  EXPECT_EQ(feedback->basic->left_encoder, 65534);
  EXPECT_EQ(feedback->basic->right_encoder, 16);
  EXPECT_EQ(feedback->basic->left_pwm, -100);
  EXPECT_EQ(feedback->basic->right_pwm, 100);
  EXPECT_EQ(feedback->basic->buttons, 1);
  EXPECT_EQ(feedback->basic->charger, 22);
  EXPECT_EQ(feedback->basic->battery_dv, 163);
  EXPECT_EQ(feedback->basic->overcurrent, 2);
  ASSERT_TRUE(feedback->inertial.has_value());
  EXPECT_EQ(feedback->inertial->angle_cdeg, 9000);
  EXPECT_EQ(feedback->inertial->angle_rate_cdeg, -100);
  EXPECT_EQ(feedback->hardware_version->ToString(), "1.0.4");
  EXPECT_EQ(feedback->firmware_version->ToString(), "1.2.0");
  EXPECT_EQ((*feedback->unique_id)[0], 0x12345678u);
  EXPECT_EQ((*feedback->unique_id)[2], 2u);
  EXPECT_EQ(feedback->other_sub_payloads, 2);
}

TEST(KobukiProtocol, MalformedFeedbackIsRefused) {
  Bytes truncated = BasicSensorDataSubPayload();
  truncated.pop_back();
  EXPECT_FALSE(ParseFeedback(truncated).has_value());
  Bytes wrong_length = BasicSensorDataSubPayload();
  wrong_length[1] = 14;
  wrong_length.pop_back();
  EXPECT_FALSE(ParseFeedback(wrong_length).has_value());
  EXPECT_FALSE(ParseFeedback({0x03}).has_value());
}

TEST(KobukiProtocol, ParserResyncsAfterGarbageSplitPacketsAndBadChecksums) {
  const Bytes good = EncodePacket(BasicSensorDataSubPayload());
  Bytes corrupt = good;
  corrupt.back() ^= 0x5A;
  // Garbage with a false header whose "packet" swallows the start of a good one.
  Bytes stream = {0x00, 0xAA, 0x13, 0xAA, 0x55, 0x08, 0x01};
  stream = Concat(Concat(Concat(stream, good), corrupt), good);
  stream.push_back(0xAA);  // half a header at the end

  PacketParser parser;
  std::vector<Bytes> payloads;
  // In pieces of 5 bytes, as a serial port may hand them over.
  for (std::size_t at = 0; at < stream.size(); at += 5) {
    parser.Push(stream.data() + at, std::min<std::size_t>(5, stream.size() - at), &payloads);
  }
  ASSERT_EQ(payloads.size(), 2u);
  EXPECT_EQ(payloads[0], BasicSensorDataSubPayload());
  EXPECT_EQ(payloads[1], BasicSensorDataSubPayload());
  EXPECT_EQ(parser.checksum_errors(), 2);  // the false header's "packet" and the corrupt one
  // The trailing 0xAA waits for its partner: with 0x55 and a packet it is a header.
  const Bytes rest(good.begin() + 1, good.end());
  parser.Push(rest.data(), rest.size(), &payloads);
  EXPECT_EQ(payloads.size(), 3u);
}

}  // namespace
}  // namespace aslam::kobuki
