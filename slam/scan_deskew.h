#pragma once

// Motion compensation ("deskew") of a swept lidar scan. A spinning head measures
// its beams one after another over its period (an RPLidar A1: 0.18 s, while the
// robot may turn 0.3 rad); each beam's end point is re-expressed in the sensor
// frame at the scan's reference time (utime), using the base's motion between
// then and the beam's own time, and the points are binned back into the scan's
// beams as seen from the reference pose.

#include <functional>

#include "common/pose2d.h"
#include "common/sensor_types.h"

namespace aslam {

// The base at `seconds_after_utime` in the frame of the base at the scan's utime.
using BaseMotion = std::function<Pose2d(double seconds_after_utime)>;

// The scan as an instantaneous one at scan.utime (beam_time_s empty). A re-binned beam
// keeps the nearest of the end points that fall into it (the one an instantaneous beam
// would see); a beam that receives none, or only points outside [range_min, range_max],
// reads 0 (no return). A beam's end point may move by up to half an angle increment
// across its bin. A scan without beam times is returned unchanged.
LidarScan DeskewScan(const LidarScan& scan, const BaseMotion& base_motion);

}  // namespace aslam
