// aslam-procman: process manager in the spirit of libbot2's procman.
//   aslam-procman deputy --config LAUNCH.yaml [--lcm-url URL] [--log-dir DIR]
//                        [--vars K=V,...] [--exit-when NAME]
//   aslam-procman start|stop|restart NAME_OR_GROUP [--lcm-url URL] [--wait-s S]
//   aslam-procman status [--lcm-url URL]
// The deputy runs the launch config's processes and exits when SIGINT/SIGTERM
// (or --exit-when) has stopped them all: 0, or 1 if any child failed.
// Parsing and dispatch: procman/procman_commands.h.

#include "procman/procman_commands.h"

int main(int argc, char** argv) { return aslam::RunProcmanCommand(argc, argv); }
