#include "drivers/sim/lidar_models.h"

#include <cmath>
#include <stdexcept>

namespace aslam {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

LidarOptions Ideal() { return LidarOptions{}; }

// Slamtec RPLIDAR A1M8 datasheet: 5.5 Hz typical scan rate, 0.15-12 m, express mode
// 4000 samples/s (720 a turn at 5.5 Hz: 0.5°), accuracy about 1 % of range; turns clockwise.
LidarOptions RplidarA1() {
  LidarOptions o;
  o.model = "rplidar_a1";
  o.num_beams = 720;
  o.rate_hz = 5.5;
  o.range_min_m = 0.15;
  o.range_max_m = 12.0;
  o.noise_sigma_m = 0.005;
  o.noise_sigma_fraction = 0.01;
  o.swept = true;
  o.clockwise = true;
  return o;
}

// Slamtec RPLIDAR A2M8 datasheet: 10 Hz typical, 0.15-12 m, 8000 samples/s (800 a turn:
// 0.45°), accuracy about 1 % of range; turns clockwise.
LidarOptions RplidarA2() {
  LidarOptions o = RplidarA1();
  o.model = "rplidar_a2";
  o.num_beams = 800;
  o.rate_hz = 10.0;
  return o;
}

// Hokuyo UST-10LX specification: 25 ms scan (40 Hz), 270° in 0.25° steps (1081 beams, ARES
// 1440), 0.06-10 m guaranteed, accuracy ±40 mm; sweeps counter-clockwise.
LidarOptions HokuyoUst10() {
  LidarOptions o;
  o.model = "hokuyo_ust10";
  o.num_beams = 1081;
  o.rate_hz = 40.0;
  o.angle_min_rad = -135.0 * kDegToRad;
  o.fov_rad = 1081 * 0.25 * kDegToRad;  // beam i at angle_min + i * fov / num_beams = 0.25° steps
  o.range_min_m = 0.06;
  o.range_max_m = 10.0;
  o.noise_sigma_m = 0.02;
  o.noise_sigma_fraction = 0.0;
  o.swept = true;
  o.clockwise = false;
  return o;
}

// Hokuyo URG-04LX-UG01 (SCIP 2.0 PP: ARES 1024, AMIN 44, AMAX 725, AFRT 384, 600 rpm,
// DMIN 20 mm, DMAX 5600 mm): 682 beams of 360/1024°, 10 Hz, ±30 mm to 1 m then ±3 %.
LidarOptions HokuyoUrg04() {
  LidarOptions o;
  o.model = "hokuyo_urg04";
  o.num_beams = 682;
  o.rate_hz = 10.0;
  const double step_rad = 2.0 * M_PI / 1024;
  o.angle_min_rad = (44 - 384) * step_rad;
  o.fov_rad = 682 * step_rad;
  o.range_min_m = 0.02;
  o.range_max_m = 5.6;
  o.noise_sigma_m = 0.01;
  o.noise_sigma_fraction = 0.01;
  o.swept = true;
  o.clockwise = false;
  return o;
}

}  // namespace

const std::vector<std::string>& LidarModelNames() {
  static const std::vector<std::string> names = {"ideal", "rplidar_a1", "rplidar_a2",
                                                 "hokuyo_ust10", "hokuyo_urg04"};
  return names;
}

LidarOptions LidarModelOptions(const std::string& model) {
  if (model == "ideal") return Ideal();
  if (model == "rplidar_a1") return RplidarA1();
  if (model == "rplidar_a2") return RplidarA2();
  if (model == "hokuyo_ust10") return HokuyoUst10();
  if (model == "hokuyo_urg04") return HokuyoUrg04();
  std::string known;
  for (const std::string& name : LidarModelNames()) known += (known.empty() ? "" : ", ") + name;
  throw std::invalid_argument("unknown lidar model '" + model + "' (known: " + known + ")");
}

}  // namespace aslam
