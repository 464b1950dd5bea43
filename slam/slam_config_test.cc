#include "slam/slam_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "common/config_testing.h"

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kShippedConfig = ShippedConfigPath();

std::string ErrorOf(const std::string& yaml) { return ConfigErrorOf(LoadSlamConfig, yaml, "slam"); }

// Every field, exactly: the shipped file must spell the built-in defaults.
void ExpectSame(const SlamConfig& a, const SlamConfig& b) {
  const SlamOptions& x = a.slam;
  const SlamOptions& y = b.slam;
  EXPECT_EQ(x.keyframe.travel_m, y.keyframe.travel_m);
  EXPECT_EQ(x.keyframe.rotation_rad, y.keyframe.rotation_rad);
  EXPECT_EQ(x.map_thinning.enabled, y.map_thinning.enabled);
  EXPECT_EQ(x.map_thinning.max_revealed_area_m2, y.map_thinning.max_revealed_area_m2);
  EXPECT_EQ(x.map_thinning.max_travel_m, y.map_thinning.max_travel_m);
  EXPECT_EQ(x.map_thinning.max_rotation_rad, y.map_thinning.max_rotation_rad);

  EXPECT_EQ(x.front_end.point_spacing_m, y.front_end.point_spacing_m);
  EXPECT_EQ(x.front_end.local_map_keyframes, y.front_end.local_map_keyframes);
  EXPECT_EQ(x.front_end.window.linear_m, y.front_end.window.linear_m);
  EXPECT_EQ(x.front_end.window.angular_rad, y.front_end.window.angular_rad);
  EXPECT_EQ(x.front_end.min_response, y.front_end.min_response);
  EXPECT_EQ(x.front_end.odometry_sigma_m, y.front_end.odometry_sigma_m);
  EXPECT_EQ(x.front_end.odometry_sigma_rad, y.front_end.odometry_sigma_rad);

  EXPECT_EQ(x.loop_closure.enabled, y.loop_closure.enabled);
  EXPECT_EQ(x.loop_closure.search_radius_m, y.loop_closure.search_radius_m);
  EXPECT_EQ(x.loop_closure.recent_chain_keyframes, y.loop_closure.recent_chain_keyframes);
  EXPECT_EQ(x.loop_closure.neighbour_keyframes, y.loop_closure.neighbour_keyframes);
  EXPECT_EQ(x.loop_closure.window.linear_m, y.loop_closure.window.linear_m);
  EXPECT_EQ(x.loop_closure.window.angular_rad, y.loop_closure.window.angular_rad);
  EXPECT_EQ(x.loop_closure.min_response, y.loop_closure.min_response);
  EXPECT_EQ(x.loop_closure.keyframes_between_attempts, y.loop_closure.keyframes_between_attempts);
  EXPECT_EQ(x.loop_closure.max_chi_square, y.loop_closure.max_chi_square);
  EXPECT_EQ(x.loop_closure.map_rerender_tolerance_m, y.loop_closure.map_rerender_tolerance_m);

  EXPECT_EQ(x.scan_matcher.resolution_m, y.scan_matcher.resolution_m);
  EXPECT_EQ(x.scan_matcher.smear_sigma_m, y.scan_matcher.smear_sigma_m);
  EXPECT_EQ(x.scan_matcher.coarse_factor, y.scan_matcher.coarse_factor);
  EXPECT_EQ(x.scan_matcher.angular_step_rad, y.scan_matcher.angular_step_rad);
  EXPECT_EQ(x.scan_matcher.max_point_range_m, y.scan_matcher.max_point_range_m);
  EXPECT_EQ(x.scan_matcher.coarse_levels, y.scan_matcher.coarse_levels);
  EXPECT_EQ(x.scan_matcher.window_edge_penalty, y.scan_matcher.window_edge_penalty);
  EXPECT_EQ(x.scan_matcher.covariance_response_gain, y.scan_matcher.covariance_response_gain);
  EXPECT_EQ(x.scan_matcher.covariance_radius_m, y.scan_matcher.covariance_radius_m);
  EXPECT_EQ(x.scan_matcher.covariance_radius_rad, y.scan_matcher.covariance_radius_rad);
  EXPECT_EQ(x.scan_matcher.min_stddev_m, y.scan_matcher.min_stddev_m);
  EXPECT_EQ(x.scan_matcher.min_stddev_rad, y.scan_matcher.min_stddev_rad);

  EXPECT_EQ(x.optimizer.max_iterations, y.optimizer.max_iterations);
  EXPECT_EQ(x.optimizer.function_tolerance, y.optimizer.function_tolerance);
  EXPECT_EQ(x.optimizer.loop_closure_loss_scale, y.optimizer.loop_closure_loss_scale);
  EXPECT_EQ(x.optimizer.num_threads, y.optimizer.num_threads);

  EXPECT_EQ(x.mapper.resolution_m, y.mapper.resolution_m);
  EXPECT_EQ(x.mapper.log_odds_hit, y.mapper.log_odds_hit);
  EXPECT_EQ(x.mapper.log_odds_miss, y.mapper.log_odds_miss);
  EXPECT_EQ(x.mapper.log_odds_min, y.mapper.log_odds_min);
  EXPECT_EQ(x.mapper.log_odds_max, y.mapper.log_odds_max);
  EXPECT_EQ(x.mapper.no_return_clear_m, y.mapper.no_return_clear_m);
  EXPECT_EQ(x.mapper.growth_margin_m, y.mapper.growth_margin_m);
  EXPECT_EQ(x.mapper.free_threshold, y.mapper.free_threshold);
  EXPECT_EQ(x.mapper.occupied_threshold, y.mapper.occupied_threshold);
  EXPECT_EQ(x.mapper.submap_keyframes, y.mapper.submap_keyframes);

  EXPECT_EQ(x.input.min_valid_points, y.input.min_valid_points);
  EXPECT_EQ(x.input.max_linear_speed_mps, y.input.max_linear_speed_mps);
  EXPECT_EQ(x.input.max_angular_speed_radps, y.input.max_angular_speed_radps);
  EXPECT_EQ(x.input.odometry_buffer_s, y.input.odometry_buffer_s);
  EXPECT_EQ(x.input.max_time_gap_s, y.input.max_time_gap_s);
  EXPECT_EQ(x.input.resync_messages, y.input.resync_messages);
  EXPECT_EQ(x.input.deskew, y.input.deskew);
  EXPECT_EQ(x.input.deskew_max_extrapolation_s, y.input.deskew_max_extrapolation_s);

  EXPECT_EQ(a.node.map_period_s, b.node.map_period_s);
  EXPECT_EQ(a.node.republish_period_s, b.node.republish_period_s);
  EXPECT_EQ(a.node.map_encoding, b.node.map_encoding);
}

// Tripwire: a field added to an options struct changes its size (mostly), and
// then needs a key in slam_config.cc, a line in config/aslam.yaml and a line above.
struct KeyframeFields {
  double d[2];
};
struct MapThinningFields {
  bool b0;
  double d[3];
};
struct FrontEndFields {
  double d0;
  int i0;
  double d[5];
};
struct LoopClosureFields {
  bool b0;
  double d0;
  int i[2];
  double d[3];
  int i2;
  double d2[2];
};
struct ScanMatcherFields {
  double d[2];
  int i0;
  double d1[2];
  int i1;
  double d2[6];
};
struct OptimizerFields {
  int i0;
  double d[2];
  int i1;
};
struct MapperFields {
  double d[9];
  int i;
};
struct InputFields {
  int i0;
  double d[4];
  int i1;
  bool b;
  double d2;
};
static_assert(sizeof(KeyframeOptions) == sizeof(KeyframeFields));
static_assert(sizeof(MapThinningOptions) == sizeof(MapThinningFields));
static_assert(sizeof(FrontEndOptions) == sizeof(FrontEndFields));
static_assert(sizeof(LoopClosureOptions) == sizeof(LoopClosureFields));
static_assert(sizeof(ScanMatcherOptions) == sizeof(ScanMatcherFields));
static_assert(sizeof(PoseGraphOptimizerOptions) == sizeof(OptimizerFields));
static_assert(sizeof(OccupancyMapperOptions) == sizeof(MapperFields));
static_assert(sizeof(InputOptions) == sizeof(InputFields));
struct NodeFields {
  double d[2];
  int e;
};
static_assert(sizeof(SlamNodeOptions) == sizeof(NodeFields));

TEST(SlamConfig, ShippedConfigLoadsAndHoldsTheDefaults) {
  const SlamConfig shipped = LoadSlamConfigFromFile(kShippedConfig);
  ExpectSame(shipped, SlamConfig{});
  // The issue's figures (#3), so the defaults cannot drift unnoticed.
  EXPECT_EQ(shipped.slam.keyframe.travel_m, 0.3);
  EXPECT_EQ(shipped.slam.keyframe.rotation_rad, 0.35);
  EXPECT_EQ(shipped.slam.front_end.window.linear_m, 0.3);
  EXPECT_EQ(shipped.slam.front_end.window.angular_rad, 0.35);
  EXPECT_EQ(shipped.slam.loop_closure.search_radius_m, 4.0);
  EXPECT_EQ(shipped.slam.mapper.resolution_m, 0.05);
  EXPECT_EQ(shipped.node.map_period_s, 1.0);
  // The library-only entry point reads the same section.
  EXPECT_EQ(LoadSlamOptionsFromFile(kShippedConfig).loop_closure.max_chi_square,
            shipped.slam.loop_closure.max_chi_square);
}

TEST(SlamConfig, EmptyFileNameOrSectionGivesDefaults) {
  ExpectSame(LoadSlamConfigFromFile(""), SlamConfig{});
  ExpectSame(LoadSlamConfig(ConfigReader::FromString("nav: {}\n", "slam")), SlamConfig{});
}

// Every key set to a value other than its default lands in its own field.
TEST(SlamConfig, EveryKeyReachesItsField) {
  const SlamConfig c = LoadSlamConfig(ConfigReader::FromString(R"(
slam:
  keyframe: {travel_m: 0.4, rotation_rad: 0.3}
  map_thinning:
    enabled: false
    max_revealed_area_m2: 0.08
    max_travel_m: 2.0
    max_rotation_rad: 0.9
  front_end:
    point_spacing_m: 0.04
    local_map_keyframes: 12
    window: {linear_m: 0.25, angular_rad: 0.3}
    min_response: 0.35
    odometry_sigma_m: 0.06
    odometry_sigma_rad: 0.04
  loop_closure:
    enabled: false
    search_radius_m: 5.0
    recent_chain_keyframes: 25
    neighbour_keyframes: 4
    window: {linear_m: 1.5, angular_rad: 0.6}
    min_response: 0.6
    keyframes_between_attempts: 3
    max_chi_square: 20.0
    map_rerender_tolerance_m: 0.05
  scan_matcher:
    resolution_m: 0.04
    smear_sigma_m: 0.06
    coarse_factor: 3
    coarse_levels: 4
    angular_step_rad: 0.01
    max_point_range_m: 10.0
    window_edge_penalty: 0.03
    covariance_response_gain: 90.0
    covariance_radius_m: 0.25
    covariance_radius_rad: 0.12
    min_stddev_m: 0.03
    min_stddev_rad: 0.006
  optimizer: {max_iterations: 40, function_tolerance: 1.0e-7, loop_closure_loss_scale: 2.0,
              num_threads: 2}
  mapper:
    resolution_m: 0.1
    log_odds_hit: 0.9
    log_odds_miss: -0.3
    log_odds_min: -2.5
    log_odds_max: 3.0
    no_return_clear_m: 1.0
    growth_margin_m: 3.0
    free_threshold: 0.2
    occupied_threshold: 0.7
    submap_keyframes: 7
  input:
    min_valid_points: 30
    max_linear_speed_mps: 2.0
    max_angular_speed_radps: 6.0
    odometry_buffer_s: 4.0
    max_time_gap_s: 2.5
    resync_messages: 5
    deskew: false
    deskew_max_extrapolation_s: 0.05
  node: {map_period_s: 2.0, republish_period_s: 7.5, map_encoding: raw}
)",
                                                               "slam"));
  const SlamOptions& o = c.slam;
  EXPECT_EQ(o.keyframe.travel_m, 0.4);
  EXPECT_EQ(o.keyframe.rotation_rad, 0.3);
  EXPECT_FALSE(o.map_thinning.enabled);
  EXPECT_EQ(o.map_thinning.max_revealed_area_m2, 0.08);
  EXPECT_EQ(o.map_thinning.max_travel_m, 2.0);
  EXPECT_EQ(o.map_thinning.max_rotation_rad, 0.9);
  EXPECT_EQ(o.front_end.point_spacing_m, 0.04);
  EXPECT_EQ(o.front_end.local_map_keyframes, 12);
  EXPECT_EQ(o.front_end.window.linear_m, 0.25);
  EXPECT_EQ(o.front_end.window.angular_rad, 0.3);
  EXPECT_EQ(o.front_end.min_response, 0.35);
  EXPECT_EQ(o.front_end.odometry_sigma_m, 0.06);
  EXPECT_EQ(o.front_end.odometry_sigma_rad, 0.04);
  EXPECT_FALSE(o.loop_closure.enabled);
  EXPECT_EQ(o.loop_closure.search_radius_m, 5.0);
  EXPECT_EQ(o.loop_closure.recent_chain_keyframes, 25);
  EXPECT_EQ(o.loop_closure.neighbour_keyframes, 4);
  EXPECT_EQ(o.loop_closure.window.linear_m, 1.5);
  EXPECT_EQ(o.loop_closure.window.angular_rad, 0.6);
  EXPECT_EQ(o.loop_closure.min_response, 0.6);
  EXPECT_EQ(o.loop_closure.keyframes_between_attempts, 3);
  EXPECT_EQ(o.loop_closure.max_chi_square, 20.0);
  EXPECT_EQ(o.loop_closure.map_rerender_tolerance_m, 0.05);
  EXPECT_EQ(o.scan_matcher.resolution_m, 0.04);
  EXPECT_EQ(o.scan_matcher.smear_sigma_m, 0.06);
  EXPECT_EQ(o.scan_matcher.coarse_factor, 3);
  EXPECT_EQ(o.scan_matcher.coarse_levels, 4);
  EXPECT_EQ(o.scan_matcher.angular_step_rad, 0.01);
  EXPECT_EQ(o.scan_matcher.max_point_range_m, 10.0);
  EXPECT_EQ(o.scan_matcher.window_edge_penalty, 0.03);
  EXPECT_EQ(o.scan_matcher.covariance_response_gain, 90.0);
  EXPECT_EQ(o.scan_matcher.covariance_radius_m, 0.25);
  EXPECT_EQ(o.scan_matcher.covariance_radius_rad, 0.12);
  EXPECT_EQ(o.scan_matcher.min_stddev_m, 0.03);
  EXPECT_EQ(o.scan_matcher.min_stddev_rad, 0.006);
  EXPECT_EQ(o.optimizer.max_iterations, 40);
  EXPECT_EQ(o.optimizer.function_tolerance, 1e-7);
  EXPECT_EQ(o.optimizer.loop_closure_loss_scale, 2.0);
  EXPECT_EQ(o.optimizer.num_threads, 2);
  EXPECT_EQ(o.mapper.resolution_m, 0.1);
  EXPECT_EQ(o.mapper.log_odds_hit, 0.9);
  EXPECT_EQ(o.mapper.log_odds_miss, -0.3);
  EXPECT_EQ(o.mapper.log_odds_min, -2.5);
  EXPECT_EQ(o.mapper.log_odds_max, 3.0);
  EXPECT_EQ(o.mapper.no_return_clear_m, 1.0);
  EXPECT_EQ(o.mapper.growth_margin_m, 3.0);
  EXPECT_EQ(o.mapper.free_threshold, 0.2);
  EXPECT_EQ(o.mapper.occupied_threshold, 0.7);
  EXPECT_EQ(o.mapper.submap_keyframes, 7);
  EXPECT_EQ(o.input.min_valid_points, 30);
  EXPECT_EQ(o.input.max_linear_speed_mps, 2.0);
  EXPECT_EQ(o.input.max_angular_speed_radps, 6.0);
  EXPECT_EQ(o.input.odometry_buffer_s, 4.0);
  EXPECT_EQ(o.input.max_time_gap_s, 2.5);
  EXPECT_EQ(o.input.resync_messages, 5);
  EXPECT_FALSE(o.input.deskew);
  EXPECT_EQ(o.input.deskew_max_extrapolation_s, 0.05);
  EXPECT_EQ(c.node.map_period_s, 2.0);
  EXPECT_EQ(c.node.republish_period_s, 7.5);
  EXPECT_EQ(c.node.map_encoding, SlamNodeOptions::MapEncoding::kRaw);
}

TEST(SlamConfig, BadValuesNameFileKeyAndValue) {
  EXPECT_THAT(
      ErrorOf("slam:\n  keyframe:\n    travel_m: -0.3\n"),
      AllOf(HasSubstr("test.yaml:3"), HasSubstr("slam.keyframe.travel_m"), HasSubstr("'-0.3'")));
  EXPECT_THAT(ErrorOf("slam:\n  front_end:\n    window: {linear_m: wide}\n"),
              AllOf(HasSubstr("test.yaml:3"), HasSubstr("slam.front_end.window.linear_m"),
                    HasSubstr("'wide'")));
  EXPECT_THAT(ErrorOf("slam:\n  loop_closure: {min_response: 1.5}\n"),
              AllOf(HasSubstr("slam.loop_closure.min_response"), HasSubstr("'1.5'")));
  EXPECT_THAT(ErrorOf("slam:\n  input: {min_valid_points: 0}\n"),
              AllOf(HasSubstr("slam.input.min_valid_points"), HasSubstr("'0'")));
  EXPECT_THAT(ErrorOf("slam:\n  mapper: {log_odds_miss: 0.4}\n"),
              AllOf(HasSubstr("slam.mapper.log_odds_miss"), HasSubstr("'0.4'")));
  EXPECT_THAT(ErrorOf("slam:\n  loop_closure: {enabled: maybe}\n"),
              AllOf(HasSubstr("slam.loop_closure.enabled"), HasSubstr("'maybe'")));
  EXPECT_THAT(ErrorOf("slam:\n  map_thinning: {max_revealed_area_m2: -1}\n"),
              AllOf(HasSubstr("slam.map_thinning.max_revealed_area_m2"), HasSubstr("'-1'")));
  EXPECT_THAT(ErrorOf("slam:\n  node: {map_period_s: -1}\n"),
              AllOf(HasSubstr("slam.node.map_period_s"), HasSubstr("'-1'")));
  EXPECT_THAT(
      ErrorOf("slam:\n  node: {map_encoding: png}\n"),
      AllOf(HasSubstr("slam.node.map_encoding"), HasSubstr("'png'"), HasSubstr("zlib or raw")));
}

TEST(SlamConfig, UnknownKeysAreNamed) {
  EXPECT_THAT(ErrorOf("slam:\n  scan_matcher:\n    resolution: 0.05\n"),
              AllOf(HasSubstr("test.yaml:3"), HasSubstr("slam.scan_matcher.resolution"),
                    HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("slam:\n  loop_closure:\n    window: {linear_m: 2.0, yaw_rad: 0.5}\n"),
              AllOf(HasSubstr("slam.loop_closure.window.yaw_rad"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("slam:\n  backend: {}\n"),
              AllOf(HasSubstr("slam.backend"), HasSubstr("unknown key")));
}

TEST(SlamConfig, CrossFieldChecksFailClearly) {
  // Candidates inside the sequential local map would close no loop.
  EXPECT_THAT(ErrorOf("slam:\n  front_end: {local_map_keyframes: 20}\n"
                      "  loop_closure: {recent_chain_keyframes: 15}\n"),
              AllOf(HasSubstr("test.yaml:3"), HasSubstr("slam.loop_closure.recent_chain_keyframes"),
                    HasSubstr("'15'"), HasSubstr("local_map_keyframes = 20")));
  // A check only the scan matcher makes (pyramid size), reported against its section.
  EXPECT_THAT(
      ErrorOf("slam:\n  scan_matcher: {coarse_factor: 4, coarse_levels: 6}\n"),
      AllOf(HasSubstr("test.yaml"), HasSubstr("slam.scan_matcher"), HasSubstr("coarse_levels")));
}

}  // namespace
}  // namespace aslam
