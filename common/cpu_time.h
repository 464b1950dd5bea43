#pragma once

// CPU time, for the cost reports of in-process runs (docs/architecture.md §4):
// what a node's handlers cost, whatever else shares the machine.

namespace aslam {

// CPU seconds the calling thread has run (user + system).
double ThreadCpuSeconds();

}  // namespace aslam
