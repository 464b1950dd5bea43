// aslam: the product's command. `aslam explore` explores a world and leaves a
// run folder behind (eval/run_outputs.h). --inproc hosts every node in this
// process (eval/explore_runner.h); process mode (the default) runs them under
// aslam-procman on a private LCM URL (eval/explore_process.h). `aslam bench`
// runs the paper's experiment matrix and writes its tables and figures
// (eval/bench.h); `aslam log-stats` reads a run's lcm log for CPU and
// latency figures (eval/log_stats.h). Parsing and dispatch: eval/aslam_commands.h.

#include "eval/aslam_commands.h"

int main(int argc, char** argv) { return aslam::RunAslamCommand(argc, argv); }
