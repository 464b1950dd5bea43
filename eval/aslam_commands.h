#pragma once

// The `aslam` command's subcommands, parsed and run: explore (eval/explore_runner.h
// in-process, eval/explore_process.h as processes, eval/run_outputs.h for the run
// folder), bench (eval/bench.h) and log-stats (eval/log_stats.h).

#include <string>
#include <vector>

namespace aslam {

// Removes every `--set X`, `--set=X` (or -set) before a "--" from `args` (argv: program, then
// flags) and returns the Xs in order: gflags cannot repeat a flag. Throws
// std::invalid_argument for a --set without a value.
std::vector<std::string> TakeSetArguments(std::vector<char*>* args);

// `aslam COMMAND [flags]` with main's arguments: prints usage for no or an
// unknown command, parses the flags, runs the command and returns the exit code
// (0 ok, 1 failed, 2 bad usage, 130 interrupted).
int RunAslamCommand(int argc, char** argv);

}  // namespace aslam
