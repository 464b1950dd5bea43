#pragma once

// The aslam-procman command, parsed and run: `deputy` hosts a Deputy on LCM
// (procman/procman_node.h), `start|stop|restart` and `status` are the sheriff's.

namespace aslam {

// `aslam-procman VERB [ARG] [flags]` with main's arguments: parses the flags,
// runs the verb and returns the exit code: the deputy's (0, or 1 if any child
// failed), the sheriff command's, or 1 for bad usage.
int RunProcmanCommand(int argc, char** argv);

}  // namespace aslam
