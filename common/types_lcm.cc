#include "common/types_lcm.h"

#include <cmath>

namespace aslam {
namespace {

bool Finite(const Pose2d& pose) {
  return std::isfinite(pose.x_m) && std::isfinite(pose.y_m) && std::isfinite(pose.yaw_rad);
}

}  // namespace

pose2d_t ToLcm(const Pose2d& pose) {
  pose2d_t msg{};
  msg.x_m = pose.x_m;
  msg.y_m = pose.y_m;
  msg.yaw_rad = pose.yaw_rad;
  return msg;
}

Pose2d FromLcm(const pose2d_t& msg) { return {msg.x_m, msg.y_m, msg.yaw_rad}; }

lidar_scan_t ToLcm(const LidarScan& scan) {
  lidar_scan_t msg{};
  msg.utime = scan.utime;
  msg.seq = scan.seq;
  msg.sensor_pose = ToLcm(scan.sensor_pose);
  msg.angle_min_rad = static_cast<float>(scan.angle_min_rad);
  msg.angle_increment_rad = static_cast<float>(scan.angle_increment_rad);
  msg.time_increment_s = static_cast<float>(scan.time_increment_s);
  msg.range_min_m = static_cast<float>(scan.range_min_m);
  msg.range_max_m = static_cast<float>(scan.range_max_m);
  msg.num_ranges = static_cast<int32_t>(scan.range_m.size());
  msg.range_m = scan.range_m;
  return msg;
}

std::optional<LidarScan> FromLcm(const lidar_scan_t& msg) {
  LidarScan scan;
  scan.utime = msg.utime;
  scan.seq = msg.seq;
  scan.sensor_pose = FromLcm(msg.sensor_pose);
  scan.angle_min_rad = msg.angle_min_rad;
  scan.angle_increment_rad = msg.angle_increment_rad;
  scan.time_increment_s = msg.time_increment_s;
  scan.range_min_m = msg.range_min_m;
  scan.range_max_m = msg.range_max_m;
  if (!Finite(scan.sensor_pose) || !std::isfinite(scan.angle_min_rad) ||
      !std::isfinite(scan.angle_increment_rad) || !std::isfinite(scan.time_increment_s) ||
      !(scan.range_min_m >= 0.0) || !(scan.range_max_m > scan.range_min_m) ||
      !std::isfinite(scan.range_max_m)) {
    return std::nullopt;
  }
  scan.range_m = msg.range_m;
  return scan;
}

odometry_t ToLcm(const Odometry& odometry) {
  odometry_t msg{};
  msg.utime = odometry.utime;
  msg.seq = odometry.seq;
  msg.pose = ToLcm(odometry.pose);
  msg.linear_velocity_mps = odometry.linear_velocity_mps;
  msg.angular_velocity_radps = odometry.angular_velocity_radps;
  return msg;
}

std::optional<Odometry> FromLcm(const odometry_t& msg) {
  Odometry odometry{msg.utime, msg.seq, FromLcm(msg.pose), msg.linear_velocity_mps,
                    msg.angular_velocity_radps};
  if (!Finite(odometry.pose) || !std::isfinite(odometry.linear_velocity_mps) ||
      !std::isfinite(odometry.angular_velocity_radps)) {
    return std::nullopt;
  }
  return odometry;
}

velocity_command_t ToLcm(const VelocityCommand& command) {
  velocity_command_t msg{};
  msg.utime = command.utime;
  msg.linear_mps = command.linear_mps;
  msg.angular_radps = command.angular_radps;
  return msg;
}

std::optional<VelocityCommand> FromLcm(const velocity_command_t& msg) {
  if (!std::isfinite(msg.linear_mps) || !std::isfinite(msg.angular_radps)) return std::nullopt;
  return VelocityCommand{msg.utime, msg.linear_mps, msg.angular_radps};
}

pose_t ToLcm(const StampedPose& pose, const std::string& frame) {
  pose_t msg{};
  msg.utime = pose.utime;
  msg.frame = frame;
  msg.pose = ToLcm(pose.pose);
  msg.linear_velocity_mps = pose.linear_velocity_mps;
  msg.angular_velocity_radps = pose.angular_velocity_radps;
  return msg;
}

std::optional<StampedPose> FromLcm(const pose_t& msg) {
  StampedPose pose{msg.utime, FromLcm(msg.pose), msg.linear_velocity_mps,
                   msg.angular_velocity_radps};
  if (!Finite(pose.pose)) return std::nullopt;
  return pose;
}

occupancy_grid_t ToLcm(const OccupancyGrid& grid, int64_t utime, int64_t revision,
                       const std::string& frame) {
  occupancy_grid_t msg{};
  msg.utime = utime;
  msg.frame = frame;
  msg.revision = revision;
  msg.resolution_m = grid.resolution_m();
  msg.origin = ToLcm(Pose2d{grid.origin_m().x_m, grid.origin_m().y_m, 0.0});
  msg.width_cells = grid.width_cells();
  msg.height_cells = grid.height_cells();
  msg.num_cells = static_cast<int32_t>(grid.cells().size());
  msg.cells = grid.cells();
  return msg;
}

std::optional<OccupancyGrid> FromLcm(const occupancy_grid_t& msg) {
  if (msg.width_cells <= 0 || msg.height_cells <= 0 ||
      static_cast<int64_t>(msg.width_cells) * msg.height_cells != msg.num_cells ||
      !(msg.resolution_m > 0.0) || !std::isfinite(msg.resolution_m) ||
      !std::isfinite(msg.origin.x_m) || !std::isfinite(msg.origin.y_m) ||
      msg.origin.yaw_rad != 0.0) {
    return std::nullopt;
  }
  for (int8_t value : msg.cells) {
    if (value < -1 || value > 100) return std::nullopt;
  }
  OccupancyGrid grid(msg.width_cells, msg.height_cells, msg.resolution_m,
                     {msg.origin.x_m, msg.origin.y_m});
  grid.mutable_cells() = msg.cells;
  return grid;
}

}  // namespace aslam
