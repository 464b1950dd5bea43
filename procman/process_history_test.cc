#include "procman/process_history.h"

#include <signal.h>

#include <gtest/gtest.h>

namespace aslam {
namespace {

ProcessStatus Process(const std::string& name, ProcessState state, int restarts, int exit_code,
                      bool should_run = true) {
  ProcessStatus p;
  p.name = name;
  p.state = state;
  p.restarts = restarts;
  p.exit_code = exit_code;
  p.should_run = should_run;
  return p;
}

DeputyStatus Status(std::vector<ProcessStatus> processes) {
  DeputyStatus status;
  status.deputy = "explore";
  status.processes = std::move(processes);
  return status;
}

TEST(ProcessHistoryTest, AKilledProcessBroughtBackIsCountedAndNotLost) {
  ProcessHistoryTracker tracker;
  tracker.Add(Status({Process("slam", ProcessState::kRunning, 0, 0),
                      Process("nav", ProcessState::kRunning, 0, 0)}));
  EXPECT_EQ(LastEnd(tracker.processes()[0]), "-");
  tracker.Add(Status({Process("slam", ProcessState::kBackoff, 0, -SIGKILL),
                      Process("nav", ProcessState::kRunning, 0, 0)}));
  tracker.Add(Status({Process("slam", ProcessState::kRunning, 1, -SIGKILL),
                      Process("nav", ProcessState::kRunning, 0, 0)}));
  ASSERT_EQ(tracker.processes().size(), 2u);
  const ProcessHistory& slam = tracker.processes()[0];
  EXPECT_EQ(slam.name, "slam");
  EXPECT_EQ(slam.restarts, 1);
  EXPECT_EQ(slam.last_signal, SIGKILL);
  EXPECT_FALSE(slam.last_exit_code.has_value());
  EXPECT_EQ(LastEnd(slam), "SIGKILL");
  EXPECT_EQ(tracker.processes()[1].restarts, 0);
  EXPECT_FALSE(tracker.processes()[1].last_signal.has_value());
  EXPECT_EQ(RestartsSummary(tracker.processes()), "slam 1");
  EXPECT_EQ(LostProcess(tracker.processes(), "sim"), std::nullopt);
}

// Without the backoff status (a lost datagram), the restart count still tells of the end.
TEST(ProcessHistoryTest, ARestartSeenOnlyAsMoreRestartsRecordsTheEnd) {
  ProcessHistoryTracker tracker;
  tracker.Add(Status({Process("nav", ProcessState::kRunning, 0, 0)}));
  tracker.Add(Status({Process("nav", ProcessState::kRunning, 2, 6)}));
  EXPECT_EQ(tracker.processes()[0].restarts, 2);
  EXPECT_EQ(tracker.processes()[0].last_exit_code, 6);
  EXPECT_EQ(LastEnd(tracker.processes()[0]), "exit 6");
}

// The TERM of the shutdown (or of a stop order) is the deputy's doing, not an end of its own.
TEST(ProcessHistoryTest, TheShutdownDoesNotOverwriteTheLastEnd) {
  ProcessHistoryTracker tracker;
  tracker.Add(Status({Process("utility", ProcessState::kRunning, 1, -SIGSEGV)}));
  tracker.Add(Status({Process("utility", ProcessState::kStopping, 1, -SIGSEGV, false)}));
  tracker.Add(Status({Process("utility", ProcessState::kStopped, 1, -SIGTERM, false)}));
  EXPECT_EQ(tracker.processes()[0].last_signal, SIGSEGV);
  EXPECT_EQ(tracker.processes()[0].restarts, 1);
}

TEST(ProcessHistoryTest, FailedOrExitedProcessesAreLostButTheExpectedEndIsNot) {
  ProcessHistoryTracker tracker;
  tracker.Add(Status({Process("sim", ProcessState::kExited, 0, 0, false),
                      Process("slam", ProcessState::kRunning, 0, 0)}));
  EXPECT_EQ(LostProcess(tracker.processes(), "sim"), std::nullopt);
  EXPECT_EQ(tracker.processes()[0].last_exit_code, 0);

  tracker.Add(Status({Process("slam", ProcessState::kFailed, 4, 3)}));
  EXPECT_EQ(LostProcess(tracker.processes(), "sim"),
            "slam ended (exit 3) after 4 restarts and procman will not restart it");

  ProcessHistoryTracker exited;
  exited.Add(Status({Process("nav", ProcessState::kExited, 0, 0)}));
  EXPECT_EQ(LostProcess(exited.processes(), "sim"),
            "nav exited with code 0 and procman will not restart it");

  ProcessHistoryTracker killed_sim;
  killed_sim.Add(Status({Process("sim", ProcessState::kFailed, 0, -SIGKILL, false)}));
  EXPECT_EQ(LostProcess(killed_sim.processes(), "sim"),
            "sim ended (SIGKILL) and procman will not restart it");
}

TEST(ProcessHistoryTest, SignalNamesAndJson) {
  EXPECT_EQ(SignalName(SIGKILL), "SIGKILL");
  EXPECT_EQ(SignalName(SIGTERM), "SIGTERM");
  EXPECT_EQ(SignalName(1000), "signal 1000");

  ProcessHistoryTracker tracker;
  tracker.Add(Status({Process("slam", ProcessState::kRunning, 1, -SIGKILL),
                      Process("nav", ProcessState::kBackoff, 0, 2)}));
  EXPECT_EQ(ProcessHistoriesJson(tracker.processes(), "  "),
            "{\n"
            "    \"slam\": {\"restarts\": 1, \"last_exit_code\": null, \"last_signal\": "
            "\"SIGKILL\"},\n"
            "    \"nav\": {\"restarts\": 0, \"last_exit_code\": 2, \"last_signal\": null}\n"
            "  }");
  EXPECT_EQ(ProcessHistoriesJson({}, "  "), "{}");
}

}  // namespace
}  // namespace aslam
