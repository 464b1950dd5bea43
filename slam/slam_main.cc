// aslam-slam: the SLAM process. Builds the pose graph and the occupancy grid
// from ODOMETRY and LIDAR_SCAN; publishes SLAM_POSE, POSE_GRAPH and SLAM_MAP.
// With --out-dir, writes map.yaml + map.pgm and graph.g2o there on SIGUSR1
// and at exit. With --journal-dir, records the graph in slam.journal there and
// resumes from it after a restart; --resume continues an earlier run's journal.
// SIGINT/SIGTERM write the outputs, print the counters, exit 0 (slam/slam_process.h).

#include <gflags/gflags.h>

#include "common/flags.h"
#include "slam/slam_process.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "config file with a `slam:` section (default: built-in defaults)");
DEFINE_string(out_dir, "",
              "folder for map.yaml, map.pgm and graph.g2o, written on SIGUSR1 and at exit "
              "(default: none)");

DEFINE_string(journal_dir, "",
              "folder of slam.journal, the graph recorded as it grows; resumed from when it "
              "exists (a restart) (default: none)");
DEFINE_string(resume, "", "continue from DIR/slam.journal of an earlier run (default: none)");

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
                    "aslam-slam [--config FILE] [--lcm-url URL] [--out-dir DIR] "
                    "[--journal-dir DIR] [--resume DIR]");
  return aslam::RunSlamProcess(
      {FLAGS_lcm_url, FLAGS_config, FLAGS_out_dir, FLAGS_journal_dir, FLAGS_resume});
}
