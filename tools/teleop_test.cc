#include "tools/teleop.h"

#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/config.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;

std::vector<int> Decode(const std::string& bytes) {
  KeyDecoder decoder;
  std::vector<int> keys;
  for (unsigned char byte : bytes) {
    if (const auto key = decoder.Feed(byte)) keys.push_back(*key);
  }
  return keys;
}

TEST(KeyDecoder, PassesPlainBytesAndDecodesArrowKeys) {
  EXPECT_EQ(Decode("ik, q"), (std::vector<int>{'i', 'k', ',', ' ', 'q'}));
  EXPECT_EQ(Decode("\x1b[A\x1b[B\x1b[C\x1b[D"),
            (std::vector<int>{kKeyUp, kKeyDown, kKeyRight, kKeyLeft}));
  EXPECT_EQ(Decode("\x1bOA\x1bOD"), (std::vector<int>{kKeyUp, kKeyLeft}));  // application mode
  EXPECT_EQ(Decode("\x1b[1;5C"), (std::vector<int>{kKeyRight}));            // Ctrl-Right
  // A function key (F5: ESC [ 1 5 ~) is swallowed whole; a lone Escape is dropped.
  EXPECT_EQ(Decode("\x1b[15~i"), (std::vector<int>{'i'}));
  EXPECT_EQ(Decode("\x1bi"), (std::vector<int>{'i'}));
  EXPECT_EQ(Decode("\x03"), (std::vector<int>{kKeyCtrlC}));
}

struct Expected {
  int key;
  double linear_mps;
  double angular_radps;
};

// Default limits 0.5 m/s and 1.8 rad/s, level 4 of 10: 0.2 m/s and 0.72 rad/s.
TEST(Teleop, EachMotionKeyDrivesItsWayAtTheCurrentSpeeds) {
  const std::vector<Expected> table = {
      {'i', 0.2, 0.0},  {kKeyUp, 0.2, 0.0},    {',', -0.2, 0.0},   {kKeyDown, -0.2, 0.0},
      {'j', 0.0, 0.72}, {kKeyLeft, 0.0, 0.72}, {'l', 0.0, -0.72},  {kKeyRight, 0.0, -0.72},
      {'u', 0.2, 0.72}, {'o', 0.2, -0.72},     {'m', -0.2, -0.72}, {'.', -0.2, 0.72},
      {'I', 0.2, 0.0},  // caps lock on
  };
  for (const Expected& e : table) {
    SCOPED_TRACE(e.key);
    Teleop teleop(TeleopOptions{});
    EXPECT_FALSE(teleop.moving());
    EXPECT_EQ(teleop.OnKey(e.key, 1.0), TeleopEvent::kMotion);
    EXPECT_NEAR(teleop.linear_mps(), e.linear_mps, 1e-12);
    EXPECT_NEAR(teleop.angular_radps(), e.angular_radps, 1e-12);
    EXPECT_TRUE(teleop.moving());
  }
}

TEST(Teleop, UnknownKeysChangeNothing) {
  Teleop teleop(TeleopOptions{});
  teleop.OnKey('i', 0.0);
  for (int key : std::vector<int>{'z', '1', '\n', 0x1a, 0x04}) {
    EXPECT_EQ(teleop.OnKey(key, 0.1), TeleopEvent::kIgnored) << key;
  }
  EXPECT_DOUBLE_EQ(teleop.linear_mps(), 0.2);
  EXPECT_FALSE(teleop.quit());
}

TEST(Teleop, SpeedStepsStayWithinTheRobotLimits) {
  Teleop teleop(TeleopOptions{});
  for (int i = 0; i < 20; ++i) EXPECT_EQ(teleop.OnKey('+', 0.0), TeleopEvent::kSpeed);
  EXPECT_EQ(teleop.linear_level(), 10);
  EXPECT_DOUBLE_EQ(teleop.linear_speed_mps(), 0.5);  // exactly the limit, never above
  EXPECT_DOUBLE_EQ(teleop.angular_speed_radps(), 1.8);
  teleop.OnKey('u', 0.0);
  EXPECT_DOUBLE_EQ(teleop.linear_mps(), 0.5);
  EXPECT_DOUBLE_EQ(teleop.angular_radps(), 1.8);

  for (int i = 0; i < 20; ++i) teleop.OnKey('-', 0.0);
  // The lowest step still moves: a tenth of each limit. A step while driving applies at once.
  EXPECT_NEAR(teleop.linear_mps(), 0.05, 1e-12);
  EXPECT_NEAR(teleop.angular_radps(), 0.18, 1e-12);

  // w/x the linear speed alone, e/c the angular alone.
  teleop.OnKey('w', 0.0);
  teleop.OnKey('w', 0.0);
  teleop.OnKey('c', 0.0);
  EXPECT_EQ(teleop.linear_level(), 3);
  EXPECT_EQ(teleop.angular_level(), 1);
  teleop.OnKey('e', 0.0);
  teleop.OnKey('x', 0.0);
  EXPECT_EQ(teleop.linear_level(), 2);
  EXPECT_EQ(teleop.angular_level(), 2);
}

TEST(Teleop, LimitsComeFromTheRobotSection) {
  const RobotOptions robot = LoadRobotOptions(ConfigReader::FromString(
      "robot: {max_linear_mps: 0.3, max_angular_radps: 1.0}\n", "robot", "robot.yaml"));
  Teleop teleop(TeleopOptionsFromRobot(robot));
  teleop.OnKey('i', 0.0);
  EXPECT_NEAR(teleop.linear_mps(), 0.12, 1e-12);  // 4/10 of 0.3
  for (int i = 0; i < 10; ++i) teleop.OnKey('=', 0.0);
  teleop.OnKey('o', 0.0);
  EXPECT_DOUBLE_EQ(teleop.linear_mps(), 0.3);
  EXPECT_DOUBLE_EQ(teleop.angular_radps(), -1.0);
  EXPECT_THAT(TeleopKeyMap(TeleopOptionsFromRobot(robot)), HasSubstr("0.30 m/s, 1.00 rad/s"));
}

TEST(Teleop, DeadManStopsWhenNoMotionKeyComesWithinTheTimeout) {
  TeleopOptions options;
  options.deadman_s = 0.6;
  Teleop teleop(options);
  teleop.OnKey('i', 10.0);
  EXPECT_DOUBLE_EQ(teleop.deadman_deadline_s(), 10.6);
  teleop.Update(10.59);
  EXPECT_TRUE(teleop.moving());
  teleop.Update(10.61);
  EXPECT_FALSE(teleop.moving());
  EXPECT_EQ(teleop.linear_mps(), 0.0);
  EXPECT_EQ(teleop.angular_radps(), 0.0);

  // A held key (auto-repeat every 0.5 s here) keeps it going for as long as it is held.
  for (double t = 20.0; t <= 23.0; t += 0.5) {
    teleop.OnKey('j', t);
    teleop.Update(t + 0.45);
    EXPECT_TRUE(teleop.moving()) << t;
  }
  teleop.Update(23.0 + 0.61);
  EXPECT_FALSE(teleop.moving());
}

TEST(Teleop, OnlyMotionKeysHoldTheDeadMan) {
  Teleop teleop(TeleopOptions{});
  teleop.OnKey('i', 0.0);
  teleop.OnKey('+', 0.5);
  teleop.OnKey('z', 0.55);
  EXPECT_TRUE(teleop.moving());
  teleop.Update(0.61);
  EXPECT_FALSE(teleop.moving());
}

TEST(Teleop, ZerosGoOutBrieflyAfterAStopThenItFallsSilent) {
  TeleopOptions options;
  options.zero_hold_s = 1.0;
  Teleop teleop(options);
  EXPECT_FALSE(teleop.ShouldPublish(0.0));  // nothing before the first key
  teleop.OnKey('i', 1.0);
  EXPECT_TRUE(teleop.ShouldPublish(1.5));
  teleop.Update(1.7);  // the dead man stops it at 1.7
  EXPECT_FALSE(teleop.moving());
  EXPECT_TRUE(teleop.ShouldPublish(2.6));
  EXPECT_FALSE(teleop.ShouldPublish(2.8));  // an idle teleop never fights aslam-nav
  EXPECT_EQ(teleop.deadman_deadline_s(), std::numeric_limits<double>::infinity());
}

TEST(Teleop, SpaceAndKStopAtOnce) {
  for (int key : std::vector<int>{' ', 'k', 'K'}) {
    Teleop teleop(TeleopOptions{});
    teleop.OnKey('u', 5.0);
    EXPECT_EQ(teleop.OnKey(key, 5.01), TeleopEvent::kStop);
    EXPECT_FALSE(teleop.moving());
    EXPECT_EQ(teleop.linear_mps(), 0.0);
    EXPECT_EQ(teleop.angular_radps(), 0.0);
    EXPECT_TRUE(teleop.ShouldPublish(5.5));
  }
  // A stop while idle still sends zeros (e.g. to halt a base another sender started).
  Teleop idle(TeleopOptions{});
  idle.OnKey(' ', 3.0);
  EXPECT_TRUE(idle.ShouldPublish(3.0));
}

TEST(Teleop, QAndCtrlCQuitWithAZeroCommand) {
  for (int key : std::vector<int>{'q', 'Q', kKeyCtrlC}) {
    Teleop teleop(TeleopOptions{});
    teleop.OnKey('i', 0.0);
    EXPECT_EQ(teleop.OnKey(key, 0.1), TeleopEvent::kQuit);
    EXPECT_TRUE(teleop.quit());
    EXPECT_FALSE(teleop.moving());
    // Nothing moves it after quitting.
    EXPECT_EQ(teleop.OnKey('i', 0.2), TeleopEvent::kIgnored);
    EXPECT_EQ(teleop.linear_mps(), 0.0);
  }
}

TEST(Teleop, StatusLineShowsCommandAndSpeeds) {
  Teleop teleop(TeleopOptions{});
  teleop.OnKey('o', 0.0);
  EXPECT_THAT(teleop.StatusLine(),
              HasSubstr("command +0.20 m/s -0.72 rad/s | speeds 0.20 m/s (4/10) 0.72 rad/s "
                        "(4/10) | driving"));
  teleop.OnKey('k', 0.1);
  EXPECT_THAT(teleop.StatusLine(), HasSubstr("command +0.00 m/s +0.00 rad/s"));
  EXPECT_THAT(teleop.StatusLine(), HasSubstr("stopped"));
}

TEST(Teleop, RejectsBadOptions) {
  TeleopOptions options;
  options.deadman_s = 0.0;
  EXPECT_THROW(Teleop{options}, std::invalid_argument);
  options = TeleopOptions{};
  options.max_linear_mps = -1.0;
  EXPECT_THROW(Teleop{options}, std::invalid_argument);
  options = TeleopOptions{};
  options.initial_angular_level = 11;
  EXPECT_THROW(Teleop{options}, std::invalid_argument);
  EXPECT_NO_THROW(Teleop{TeleopOptions{}});
}

}  // namespace
}  // namespace aslam
