#pragma once

// LCM channel names (lcmtypes/README.md lists type, publisher, rate, units and frame of each).

namespace aslam::channels {

inline constexpr const char* kLidarScan = "LIDAR_SCAN";
inline constexpr const char* kOdometry = "ODOMETRY";
inline constexpr const char* kSimTruth = "SIM_TRUTH";
inline constexpr const char* kSimStatus = "SIM_STATUS";
inline constexpr const char* kCmdVel = "CMD_VEL";
inline constexpr const char* kBaseStatus = "BASE_STATUS";
inline constexpr const char* kDriverStatus = "DRIVER_STATUS";
inline constexpr const char* kSlamPose = "SLAM_POSE";
inline constexpr const char* kSlamMap = "SLAM_MAP";
inline constexpr const char* kPoseGraph = "POSE_GRAPH";
inline constexpr const char* kFrontiers = "FRONTIERS";
inline constexpr const char* kUtilityScores = "UTILITY_SCORES";
inline constexpr const char* kExploreGoal = "EXPLORE_GOAL";
inline constexpr const char* kExploreStatus = "EXPLORE_STATUS";
inline constexpr const char* kExploreControl = "EXPLORE_CONTROL";
inline constexpr const char* kNavStatus = "NAV_STATUS";
inline constexpr const char* kNavPath = "NAV_PATH";
inline constexpr const char* kNavObstacles = "NAV_OBSTACLES";
inline constexpr const char* kProcmanOrders = "PROCMAN_ORDERS";
inline constexpr const char* kProcmanStatus = "PROCMAN_STATUS";

}  // namespace aslam::channels
