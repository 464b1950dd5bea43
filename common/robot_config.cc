#include "common/robot_config.h"

#include <cmath>
#include <sstream>

namespace aslam {

RobotOptions LoadRobotOptions(const ConfigReader& robot) {
  RobotOptions options;
  robot.ReadInRange("radius_m", &options.radius_m, 0.01, 5.0);
  robot.ReadInRange("clearance_margin_m", &options.clearance_margin_m, 0.0, 5.0);
  robot.ReadInRange("max_linear_mps", &options.max_linear_mps, 0.01, 20.0);
  robot.ReadInRange("max_angular_radps", &options.max_angular_radps, 0.01, 20.0);
  robot.ReadInRange("max_linear_accel_mps2", &options.max_linear_accel_mps2, 1e-3, 100.0);
  robot.ReadInRange("max_angular_accel_radps2", &options.max_angular_accel_radps2, 1e-3, 100.0);

  const ConfigReader mount = robot.Section("lidar_mount");
  Pose2d& lidar = options.lidar_mount;
  mount.ReadInRange("x_m", &lidar.x_m, -5.0, 5.0);
  mount.ReadInRange("y_m", &lidar.y_m, -5.0, 5.0);
  mount.ReadInRange("yaw_rad", &lidar.yaw_rad, -M_PI, M_PI);
  robot.CheckAllKeysUsed();

  // A lidar outside the footprint could sit inside a wall the base touches.
  if (std::hypot(lidar.x_m, lidar.y_m) > options.radius_m) {
    std::ostringstream problem;
    problem << "the lidar must lie within radius_m = " << options.radius_m
            << " m of the base centre";
    mount.Fail(lidar.x_m != 0.0 ? "x_m" : "y_m", problem.str());
  }
  return options;
}

RobotOptions LoadRobotOptionsFromFile(const std::string& file) {
  return LoadRobotOptions(ConfigReader::FromOptionalFile(file, "robot"));
}

}  // namespace aslam
