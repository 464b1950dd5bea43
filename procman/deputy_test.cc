#include "procman/deputy.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "common/test_temp_dir.h"

namespace aslam {
namespace {

// Time stands still unless the test moves it: backoff and stop timeouts become exact.
class ManualClock : public Clock {
 public:
  double NowS() const override { return now_s; }
  double now_s = 1000.0;
};

ProcessConfig Proc(const std::string& name, const std::string& shell_command,
                   RestartPolicy restart = RestartPolicy::kNever) {
  ProcessConfig p;
  p.name = name;
  p.command = "/bin/sh";
  p.args = {"-c", shell_command};
  p.restart = restart;
  return p;
}

ProcessConfig Sleeper(const std::string& name, RestartPolicy restart = RestartPolicy::kNever) {
  ProcessConfig p;
  p.name = name;
  p.command = "/bin/sleep";
  p.args = {"30"};
  p.restart = restart;
  return p;
}

bool Alive(int pid) { return pid > 0 && kill(pid, 0) == 0; }

class DeputyTest : public ::testing::Test {
 protected:
  void TearDown() override { deputy_.reset(); }  // kills and reaps what is left

  Deputy& Make(std::vector<ProcessConfig> processes, const std::string& exit_when = "",
               double stop_timeout_s = 3.0, bool reap_all_children = false) {
    LaunchConfig config;
    config.deputy = "test";
    config.stop_timeout_s = stop_timeout_s;
    config.processes = std::move(processes);
    deputy_ = std::make_unique<Deputy>(
        config, DeputyOptions{log_dir_, exit_when, reap_all_children}, clock_);
    return *deputy_;
  }

  ProcessStatus Of(const std::string& name) {
    for (const auto& p : deputy_->Status().processes) {
      if (p.name == name) return p;
    }
    ADD_FAILURE() << "no process " << name;
    return {};
  }

  // Steps the deputy until `done` holds; false after a generous timeout (an event that never came).
  template <typename Pred>
  bool StepUntil(Pred done, double timeout_s = 10.0) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (true) {
      deputy_->Step();
      if (done()) return true;
      if (std::chrono::steady_clock::now() > end) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  std::string Log(const std::string& name) {
    std::ifstream in(deputy_->LogPath(name));
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  ManualClock clock_;
  const std::string log_dir_ = TestTempDir();
  std::unique_ptr<Deputy> deputy_;
};

TEST_F(DeputyTest, StartsAndReportsFullStatus) {
  ProcessConfig p = Sleeper("sleeper");
  p.group = "naps";
  Deputy& d = Make({p});
  d.Start();
  const DeputyStatus status = d.Status();
  EXPECT_EQ(status.deputy, "test");
  EXPECT_EQ(status.pid, getpid());
  ASSERT_EQ(status.processes.size(), 1u);
  const ProcessStatus& s = status.processes[0];
  EXPECT_EQ(s.name, "sleeper");
  EXPECT_EQ(s.group, "naps");
  EXPECT_EQ(s.command_line, "/bin/sleep 30");
  EXPECT_TRUE(s.should_run);
  EXPECT_EQ(s.state, ProcessState::kRunning);
  EXPECT_TRUE(Alive(s.pid));
  EXPECT_EQ(getpgid(s.pid), s.pid);  // its own process group
  EXPECT_EQ(s.restarts, 0);
  EXPECT_EQ(s.exit_code, 0);
  EXPECT_GT(s.rss_bytes, 0);
  EXPECT_TRUE(std::filesystem::exists(d.LogPath("sleeper")));
}

TEST_F(DeputyTest, FailingChildWithRestartNeverStaysFailedAndLogsItsOutput) {
  Deputy& d = Make({Proc("fails", "echo to-stdout; echo to-stderr >&2; exit 3")});
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Of("fails").state == ProcessState::kFailed; }));
  const ProcessStatus s = Of("fails");
  EXPECT_EQ(s.exit_code, 3);
  EXPECT_EQ(s.pid, 0);
  EXPECT_EQ(s.restarts, 0);
  EXPECT_EQ(d.failures(), 1);
  EXPECT_EQ(d.ExitCode(), 1);
  const std::string log = Log("fails");
  EXPECT_NE(log.find("to-stdout"), std::string::npos) << log;
  EXPECT_NE(log.find("to-stderr"), std::string::npos) << log;
  EXPECT_NE(log.find("exit code 3"), std::string::npos) << log;
}

TEST_F(DeputyTest, CleanExitIsExitedAndNoFailure) {
  Deputy& d = Make({Proc("done", "exit 0", RestartPolicy::kOnFailure)});
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Of("done").state == ProcessState::kExited; }));
  EXPECT_EQ(Of("done").restarts, 0);  // on-failure does not restart a success
  EXPECT_EQ(d.ExitCode(), 0);
}

TEST_F(DeputyTest, OnFailureRestartsAfterExponentialBackoff) {
  ProcessConfig p = Proc("flaky", "exit 3", RestartPolicy::kOnFailure);
  p.backoff.initial_s = 5.0;
  p.backoff.factor = 2.0;
  p.backoff.max_s = 60.0;
  Deputy& d = Make({p});
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Of("flaky").state == ProcessState::kBackoff; }));
  clock_.now_s += 4.9;
  for (int i = 0; i < 20; ++i) d.Step();
  EXPECT_EQ(Of("flaky").state, ProcessState::kBackoff);  // 5 s not over yet
  EXPECT_EQ(Of("flaky").restarts, 0);
  clock_.now_s += 0.1;
  d.Step();
  EXPECT_EQ(Of("flaky").restarts, 1);
  ASSERT_TRUE(StepUntil([&] { return Of("flaky").state == ProcessState::kBackoff; }));
  clock_.now_s += 9.9;  // the second delay is 10 s
  for (int i = 0; i < 20; ++i) d.Step();
  EXPECT_EQ(Of("flaky").restarts, 1);
  clock_.now_s += 0.1;
  d.Step();
  EXPECT_EQ(Of("flaky").restarts, 2);
  EXPECT_EQ(Of("flaky").exit_code, 3);
}

// A process that fails every time is restarted give_up_after_failures - 1 times, then left
// failed with the reason in its log; a healthy run in between starts the count again.
TEST_F(DeputyTest, GivesUpAfterTheConfiguredFailuresInARow) {
  ProcessConfig p = Proc("crashes", "exit 7", RestartPolicy::kOnFailure);
  p.backoff.initial_s = 0.0;
  p.backoff.give_up_after_failures = 3;
  Deputy& d = Make({p});
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Of("crashes").state == ProcessState::kFailed; }));
  EXPECT_EQ(Of("crashes").restarts, 2);
  EXPECT_EQ(Of("crashes").exit_code, 7);
  for (int i = 0; i < 20; ++i) d.Step();
  EXPECT_EQ(Of("crashes").state, ProcessState::kFailed);  // for good
  EXPECT_EQ(Of("crashes").restarts, 2);
  EXPECT_NE(Log("crashes").find("gave up after 3 failures in a row"), std::string::npos)
      << Log("crashes");
  ASSERT_EQ(d.failures(), 3);  // three ends; giving up is no fourth
  EXPECT_NE(d.failure_reasons().back().find("crashes: exit code 7; gave up after 3"),
            std::string::npos)
      << d.failure_reasons().back();
}

TEST_F(DeputyTest, AHealthyRunStartsTheFailureCountAgain) {
  ProcessConfig p = Sleeper("healthy", RestartPolicy::kOnFailure);
  p.backoff.initial_s = 0.0;
  p.backoff.reset_after_s = 5.0;
  p.backoff.give_up_after_failures = 2;
  Deputy& d = Make({p});
  d.Start();
  for (int kill_number = 1; kill_number <= 3; ++kill_number) {
    clock_.now_s += 6.0;  // each run lasts past reset_after_s: every failure is the first
    kill(Of("healthy").pid, SIGKILL);
    ASSERT_TRUE(StepUntil([&] { return Of("healthy").restarts == kill_number; }));
    EXPECT_EQ(Of("healthy").state, ProcessState::kRunning);
  }
  kill(Of("healthy").pid, SIGKILL);  // at once this time: the second failure in a row
  ASSERT_TRUE(StepUntil([&] { return Of("healthy").state == ProcessState::kFailed; }));
  EXPECT_EQ(Of("healthy").exit_code, -SIGKILL);
  EXPECT_EQ(d.failures(), 4);
}

TEST_F(DeputyTest, AlwaysRestartsEvenAfterSuccess) {
  ProcessConfig p = Proc("loop", "exit 0", RestartPolicy::kAlways);
  p.backoff.initial_s = 0.0;
  Deputy& d = Make({p});
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Of("loop").restarts >= 3; }));
  EXPECT_EQ(d.ExitCode(), 0);
}

TEST_F(DeputyTest, NeverDoesNotRestartAKilledChild) {
  Deputy& d = Make({Sleeper("s")});
  d.Start();
  kill(Of("s").pid, SIGKILL);
  ASSERT_TRUE(StepUntil([&] { return Of("s").state == ProcessState::kFailed; }));
  EXPECT_EQ(Of("s").exit_code, -SIGKILL);
  EXPECT_EQ(Of("s").restarts, 0);
}

TEST_F(DeputyTest, SigkilledChildIsRestartedAndCounted) {
  ProcessConfig p = Sleeper("s", RestartPolicy::kOnFailure);
  p.backoff.initial_s = 0.0;
  Deputy& d = Make({p});
  d.Start();
  const int first_pid = Of("s").pid;
  kill(first_pid, SIGKILL);
  ASSERT_TRUE(StepUntil([&] { return Of("s").restarts == 1; }));
  const ProcessStatus s = Of("s");
  EXPECT_EQ(s.state, ProcessState::kRunning);
  EXPECT_NE(s.pid, first_pid);
  EXPECT_TRUE(Alive(s.pid));
  EXPECT_EQ(s.exit_code, -SIGKILL);
  EXPECT_EQ(d.failures(), 1);  // a crash is never silent, even when restarted
}

TEST_F(DeputyTest, OrdersAreAppliedIdempotently) {
  ProcessConfig b = Sleeper("b");
  b.auto_start = false;
  Deputy& d = Make({Sleeper("a"), b});
  d.Start();
  EXPECT_EQ(Of("b").state, ProcessState::kStopped);
  const DeputyOrders both{"test", {{"a", true, 0}, {"b", true, 0}}};
  EXPECT_TRUE(d.ApplyOrders(both));
  const int a_pid = Of("a").pid;
  const int b_pid = Of("b").pid;
  EXPECT_TRUE(Alive(b_pid));
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(d.ApplyOrders(both));  // repeats change nothing
  EXPECT_EQ(Of("a").pid, a_pid);
  EXPECT_EQ(Of("b").pid, b_pid);
  EXPECT_EQ(Of("b").restarts, 0);

  // Stop a: TERM, reaped as stopped, not a failure; repeating the stop changes nothing.
  const DeputyOrders stop_a{"test", {{"a", false, 0}, {"b", true, 0}}};
  EXPECT_TRUE(d.ApplyOrders(stop_a));
  EXPECT_EQ(Of("a").state, ProcessState::kStopping);
  ASSERT_TRUE(StepUntil([&] { return Of("a").state == ProcessState::kStopped; }));
  EXPECT_FALSE(Alive(a_pid));
  EXPECT_EQ(Of("a").exit_code, -SIGTERM);
  EXPECT_FALSE(Of("a").should_run);
  EXPECT_FALSE(d.ApplyOrders(stop_a));
  EXPECT_EQ(Of("a").pid, 0);
  EXPECT_EQ(d.failures(), 0);

  // Start it again in the same run; then a new run id restarts it once.
  EXPECT_TRUE(d.ApplyOrders(both));
  EXPECT_EQ(Of("a").restarts, 1);
  const int a_pid2 = Of("a").pid;
  const DeputyOrders restart_a{"test", {{"a", true, 1}, {"b", true, 0}}};
  d.ApplyOrders(restart_a);
  ASSERT_TRUE(StepUntil([&] { return Of("a").state == ProcessState::kRunning; }));
  EXPECT_NE(Of("a").pid, a_pid2);
  EXPECT_EQ(Of("a").run_id, 1);
  EXPECT_EQ(Of("a").restarts, 2);
  const int a_pid3 = Of("a").pid;
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(d.ApplyOrders(restart_a));
  d.Step();
  EXPECT_EQ(Of("a").pid, a_pid3);
  EXPECT_EQ(Of("b").pid, b_pid);  // never touched
  EXPECT_EQ(d.failures(), 0);

  // Orders for another deputy, or for names it does not have, are ignored and counted.
  EXPECT_FALSE(d.ApplyOrders(DeputyOrders{"other", {{"a", false, 1}}}));
  EXPECT_FALSE(d.ApplyOrders(DeputyOrders{"test", {{"nobody", true, 0}}}));
  EXPECT_EQ(d.ignored_orders(), 2);
  EXPECT_EQ(Of("a").state, ProcessState::kRunning);
}

TEST_F(DeputyTest, RepeatedOrderDoesNotRerunAnExitedProcessButANewRunIdDoes) {
  Deputy& d = Make({Proc("once", "exit 0")});
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Of("once").state == ProcessState::kExited; }));
  const DeputyOrders same{"test", {{"once", true, 0}}};
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(d.ApplyOrders(same));
  EXPECT_EQ(Of("once").restarts, 0);
  d.ApplyOrders(DeputyOrders{"test", {{"once", true, 1}}});
  EXPECT_EQ(Of("once").restarts, 1);
  ASSERT_TRUE(StepUntil([&] { return Of("once").state == ProcessState::kExited; }));
}

TEST_F(DeputyTest, StopEscalatesToKillAfterTheTimeout) {
  // Ignores TERM (the sleeps inherit that), and says so once it does ("re""ady" keeps
  // the word out of the log's command-line header).
  Deputy& d = Make({Proc("stubborn", "trap '' TERM; echo re\"\"ady; while :; do sleep 0.05; done")},
                   "", 3.0);
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Log("stubborn").find("ready") != std::string::npos; }));
  d.ApplyOrders(DeputyOrders{"test", {{"stubborn", false, 0}}});
  for (int i = 0; i < 20; ++i) d.Step();
  EXPECT_EQ(Of("stubborn").state, ProcessState::kStopping);
  clock_.now_s += 3.0;
  ASSERT_TRUE(StepUntil([&] { return Of("stubborn").state == ProcessState::kStopped; }));
  EXPECT_EQ(Of("stubborn").exit_code, -SIGKILL);
  EXPECT_EQ(d.failures(), 1);  // had to be killed
}

TEST_F(DeputyTest, ShutdownStopsEveryChildAndItsGroup) {
  ProcessConfig early = Sleeper("early");
  early.start_order = -1;
  ProcessConfig parent = Proc("parent", "sleep 30 & wait");  // a grandchild in its group
  parent.start_order = 5;
  Deputy& d = Make({early, Sleeper("middle"), parent});
  d.Start();
  std::vector<int> pids;
  for (const auto& p : d.Status().processes) pids.push_back(p.pid);
  d.BeginShutdown();
  ASSERT_TRUE(StepUntil([&] { return d.Finished(); }));
  for (int pid : pids) {
    EXPECT_FALSE(Alive(pid));
    // The whole group is gone (orphans are reaped by init, hence the wait).
    EXPECT_TRUE(StepUntil([&] { return kill(-pid, 0) != 0 && errno == ESRCH; }, 5.0)) << pid;
  }
  for (const auto& p : d.Status().processes) {
    EXPECT_EQ(p.state, ProcessState::kStopped) << p.name;
    EXPECT_EQ(p.pid, 0);
  }
  EXPECT_EQ(d.ExitCode(), 0);
  d.ApplyOrders(DeputyOrders{"test", {{"middle", true, 7}}});  // nothing starts any more
  d.Step();
  EXPECT_EQ(Of("middle").pid, 0);
}

TEST_F(DeputyTest, ShutdownStopsTiersInReverseStartOrder) {
  ProcessConfig first = Sleeper("first");
  first.start_order = -1;
  ProcessConfig last = Sleeper("last");
  last.start_order = 5;
  ProcessConfig stubborn =
      Proc("stubborn", "trap '' TERM; echo re\"\"ady; while :; do sleep 0.05; done");
  stubborn.start_order = 5;
  Deputy& d = Make({first, Sleeper("middle"), last, stubborn}, "", 3.0);
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Log("stubborn").find("ready") != std::string::npos; }));
  d.BeginShutdown();
  ASSERT_TRUE(StepUntil([&] { return Of("last").state == ProcessState::kStopped; }));
  // The top tier waits for its stubborn member; the lower tiers have not been touched.
  for (int i = 0; i < 20; ++i) d.Step();
  EXPECT_EQ(Of("stubborn").state, ProcessState::kStopping);
  EXPECT_EQ(Of("middle").state, ProcessState::kRunning);
  EXPECT_EQ(Of("first").state, ProcessState::kRunning);
  clock_.now_s += 3.0;  // KILL for the stubborn one, then the next tier
  ASSERT_TRUE(StepUntil([&] { return Of("middle").state == ProcessState::kStopped; }));
  ASSERT_TRUE(StepUntil([&] { return d.Finished(); }));
  EXPECT_EQ(Of("first").exit_code, -SIGTERM);
  EXPECT_EQ(Of("stubborn").exit_code, -SIGKILL);
}

TEST_F(DeputyTest, ShutdownAfterAFailureExitsNonZero) {
  Deputy& d = Make({Sleeper("s"), Proc("bad", "exit 3")});
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Of("bad").state == ProcessState::kFailed; }));
  d.BeginShutdown();
  ASSERT_TRUE(StepUntil([&] { return d.Finished(); }));
  EXPECT_EQ(d.ExitCode(), 1);
  ASSERT_EQ(d.failure_reasons().size(), 1u);
  EXPECT_EQ(d.failure_reasons()[0], "bad: exit code 3");
}

TEST_F(DeputyTest, ExitWhenShutsDownTheRestOnceTheNamedProcessEnds) {
  ProcessConfig sim = Proc("sim", "exit 0");
  sim.start_order = 1;
  Deputy& d = Make({Sleeper("slam", RestartPolicy::kAlways), sim}, "sim");
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return d.Finished(); }));
  EXPECT_EQ(Of("sim").state, ProcessState::kExited);
  EXPECT_EQ(Of("slam").state, ProcessState::kStopped);
  EXPECT_EQ(Of("slam").restarts, 0);
  EXPECT_EQ(d.ExitCode(), 0);
}

TEST_F(DeputyTest, ExitWhenMustNameAProcess) {
  EXPECT_THROW(Make({Sleeper("s")}, "sim"), std::invalid_argument);
}

TEST_F(DeputyTest, DelayedStartWaitsForTheClock) {
  ProcessConfig late = Sleeper("late");
  late.start_delay_s = 2.0;
  Deputy& d = Make({late});
  d.Start();
  d.Step();
  EXPECT_EQ(Of("late").pid, 0);
  clock_.now_s += 2.0;
  d.Step();
  EXPECT_TRUE(Alive(Of("late").pid));
}

TEST_F(DeputyTest, MissingProgramFailsWithoutRetrying) {
  ProcessConfig p;
  p.name = "ghost";
  p.command = "/nonexistent/program";
  p.restart = RestartPolicy::kOnFailure;
  Deputy& d = Make({p});
  d.Start();
  d.Step();
  EXPECT_EQ(Of("ghost").state, ProcessState::kFailed);
  EXPECT_EQ(Of("ghost").exit_code, 127);
  EXPECT_EQ(d.ExitCode(), 1);
  EXPECT_NE(Log("ghost").find("No such file"), std::string::npos) << Log("ghost");
}

TEST_F(DeputyTest, EnvironmentIsPassed) {
  ProcessConfig p = Proc("env", "echo \"value=$ASLAM_TEST_VAR\"");
  p.env["ASLAM_TEST_VAR"] = "forty two";
  Deputy& d = Make({p});
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Of("env").state == ProcessState::kExited; }));
  EXPECT_NE(Log("env").find("value=forty two"), std::string::npos) << Log("env");
}

// As aslam-procman runs it: a subreaper that reaps orphaned grandchildren, so none
// is left as a zombie. Last in this file: it changes the test process itself.
TEST_F(DeputyTest, SubreaperReapsOrphanedGrandchildren) {
  ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  Deputy& d = Make({Proc("parent", "sleep 30 & echo grandchild=$!; exit 0")}, "", 3.0, true);
  d.Start();
  ASSERT_TRUE(StepUntil([&] { return Of("parent").state == ProcessState::kExited; }));
  const std::string log = Log("parent");
  const std::size_t at = log.rfind("grandchild=");  // the last: the header holds "=$!"
  ASSERT_NE(at, std::string::npos) << log;
  const int grandchild = std::atoi(log.c_str() + at + 11);
  ASSERT_GT(grandchild, 0);
  // Killed with its group when the parent ended, then reaped: gone, not a zombie.
  EXPECT_TRUE(StepUntil([&] { return kill(grandchild, 0) != 0 && errno == ESRCH; }));
  prctl(PR_SET_CHILD_SUBREAPER, 0);
}

TEST(DeputyCpuTest, BusyChildShowsCpu) {
  const std::string dir = TestTempDir();
  {
    SteadyClock clock;
    LaunchConfig config;
    config.processes = {Proc("busy", "while :; do :; done")};
    Deputy d(config, DeputyOptions{dir, ""}, clock);
    d.Start();
    d.Status();
    double cpu = 0.0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (cpu <= 0.0 && std::chrono::steady_clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      d.Step();
      cpu = d.Status().processes[0].cpu_percent;
    }
    EXPECT_GT(cpu, 0.0);
  }
}

}  // namespace
}  // namespace aslam
