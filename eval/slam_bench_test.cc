#include "eval/slam_bench.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "common/test_temp_dir.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;

// Keyframes at 1 s and 2 s; truth and odometry at 0.5 s steps, both offset from the keyframes.
struct Trajectories {
  std::vector<TimedPose> keyframes = {{1000000, {0.0, 0.0, 0.0}},
                                      {2000000, {1.0, 0.0, 0.0}},
                                      {9000000, {2.0, 0.0, 0.0}}};  // nothing near 9 s
  std::vector<TimedPose> truth = {{1000000, {5.0, 5.0, M_PI / 2}},
                                  {1500000, {5.0, 5.5, M_PI / 2}},
                                  {2000000, {5.0, 6.1, M_PI / 2}}};
  std::vector<TimedPose> odometry = {
      {500000, {0.0, 0.0, 0.0}}, {1000000, {2.0, 0.0, 0.0}}, {2000000, {3.2, 0.0, 0.0}}};
};

TEST(OdometryAtKeyframes, RelativeToTheFirstKeyframeWithOdometry) {
  const Trajectories t;
  const std::vector<TimedPose> odometry = OdometryAtKeyframes(t.keyframes, t.odometry);
  ASSERT_EQ(odometry.size(), 2u);
  EXPECT_EQ(odometry[0].utime, 1000000);
  EXPECT_NEAR(odometry[0].pose.x_m, 0.0, 1e-12);
  EXPECT_EQ(odometry[1].utime, 2000000);
  EXPECT_NEAR(odometry[1].pose.x_m, 1.2, 1e-12);
  EXPECT_TRUE(OdometryAtKeyframes(t.keyframes, {}).empty());
}

TEST(WriteTrajectoryCsv, KeyframeTruthErrorAndOdometryPerRow) {
  const Trajectories t;
  std::ostringstream csv;
  WriteTrajectoryCsv(t.keyframes, t.truth, t.odometry, csv);
  std::istringstream lines(csv.str());
  std::string header, first, second, third, extra;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  std::getline(lines, third);
  EXPECT_FALSE(std::getline(lines, extra));
  EXPECT_EQ(header,
            "node,utime,x_m,y_m,yaw_rad,truth_x_m,truth_y_m,truth_yaw_rad,error_m,"
            "odometry_x_m,odometry_y_m,odometry_yaw_rad");
  EXPECT_EQ(first, "0,1000000,0,0,0,0,0,0,0,0,0,0");
  // Truth 1.1 m ahead of its start (turned into the keyframes' frame): error 0.1 m.
  EXPECT_THAT(second, HasSubstr("1,2000000,1,0,0,1.1,"));
  EXPECT_THAT(second, HasSubstr(",0.1,1.2,0,0"));
  EXPECT_EQ(third, "2,9000000,2,0,0,,,,,,,");  // nothing within 0.1 s
}

// Counts the events per channel of an LCM log, checking they are in time order.
std::map<std::string, int> EventsPerChannel(const std::string& path) {
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good());
  std::map<std::string, int> counts;
  int64_t last_utime = -1;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    EXPECT_GE(event->timestamp, last_utime);
    last_utime = event->timestamp;
    ++counts[event->channel];
  }
  return counts;
}

TEST(RunSlamBench, RecordsTheSimulatorAndWritesMapAndTrajectory) {
  const std::string root = ASLAM_SOURCE_DIR;
  const std::filesystem::path dir = FreshTestTempDir("bench");
  SlamBenchOptions options;
  options.world_dir = root + "/worlds/test";
  options.drive_path = root + "/config/drives/test_loop.yaml";
  options.config_path = root + "/config/aslam.yaml";
  options.duration_s = 2.0;
  options.out_dir = (dir / "out").string();
  options.record_log_path = (dir / "drive.lcmlog").string();
  ASSERT_EQ(RunSlamBench(options), 0);
  // 2 s of the simulator: odometry and truth at 50 Hz, scans at 10 Hz.
  const std::map<std::string, int> counts = EventsPerChannel(options.record_log_path);
  EXPECT_EQ(counts.size(), 3u);
  EXPECT_NEAR(counts.at("ODOMETRY"), 100, 1);
  EXPECT_NEAR(counts.at("SIM_TRUTH"), 100, 1);
  EXPECT_NEAR(counts.at("LIDAR_SCAN"), 20, 1);
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "map.yaml"));
  std::ifstream csv(dir / "out" / "trajectory.csv");
  std::string header, first_row;
  std::getline(csv, header);
  std::getline(csv, first_row);
  EXPECT_THAT(header, HasSubstr("node,utime,x_m"));
  EXPECT_THAT(first_row, HasSubstr("0,"));
}

TEST(RunSlamBench, RejectsMissingWorldOrDriveAndNegativeDuration) {
  SlamBenchOptions options;
  EXPECT_EQ(RunSlamBench(options), 2);
  options.world_dir = "worlds/test";
  options.drive_path = "drive.yaml";
  options.duration_s = -1.0;
  EXPECT_EQ(RunSlamBench(options), 2);
  options.duration_s = 0.0;
  options.drive_path = "/nonexistent/drive.yaml";
  EXPECT_EQ(RunSlamBench(options), 1);
}

}  // namespace
}  // namespace aslam
