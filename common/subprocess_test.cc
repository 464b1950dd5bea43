#include "common/subprocess.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "common/test_temp_dir.h"

namespace aslam {
namespace {

SubprocessOptions Shell(const std::string& script) {
  SubprocessOptions options;
  options.argv = {"/bin/sh", "-c", script};
  return options;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(SubprocessTest, ExitCodeIsReported) {
  Subprocess child = Subprocess::Spawn(Shell("exit 3"));
  EXPECT_TRUE(child.running());
  EXPECT_GT(child.pid(), 0);
  const ExitStatus status = child.Wait();
  EXPECT_TRUE(status.exited());
  EXPECT_FALSE(status.success());
  EXPECT_EQ(status.code, 3);
  EXPECT_EQ(status.CodeOrMinusSignal(), 3);
  EXPECT_EQ(status.Describe(), "exit code 3");
  EXPECT_FALSE(child.running());
  ASSERT_TRUE(child.Poll());  // the same answer again
  EXPECT_EQ(child.Poll()->code, 3);
}

TEST(SubprocessTest, PollDoesNotBlockWhileTheChildRuns) {
  Subprocess child = Subprocess::Spawn(Shell("sleep 30"));
  EXPECT_FALSE(child.Poll());
  EXPECT_TRUE(child.running());
  EXPECT_TRUE(child.Signal(SIGTERM));
  const ExitStatus status = child.Wait();
  EXPECT_EQ(status.signal, SIGTERM);
}

TEST(SubprocessTest, SignalThatKilledTheChildIsReported) {
  Subprocess child = Subprocess::Spawn(Shell("kill -USR1 $$; sleep 30"));
  const ExitStatus status = child.Wait();
  EXPECT_FALSE(status.exited());
  EXPECT_EQ(status.signal, SIGUSR1);
  EXPECT_EQ(status.code, 0);
  EXPECT_EQ(status.CodeOrMinusSignal(), -SIGUSR1);
  EXPECT_EQ(status.Describe().rfind("killed by signal " + std::to_string(SIGUSR1) + " (", 0), 0u)
      << status.Describe();
}

TEST(SubprocessTest, TerminateEndsAChildThatHonoursTerm) {
  Subprocess child = Subprocess::Spawn(Shell("exec sleep 30"));
  int polls = 0;
  const ExitStatus status = child.Terminate(60.0, [&] {
    ++polls;
    usleep(1000);
  });
  EXPECT_EQ(status.signal, SIGTERM);
  EXPECT_FALSE(child.killed_after_grace());
}

TEST(SubprocessTest, ChildIgnoringTermIsKilledAfterTheGracePeriod) {
  const std::string ready = TestTempPath("ready");
  std::remove(ready.c_str());
  // Ignores TERM, says so, then waits; TERM must not end it.
  Subprocess child =
      Subprocess::Spawn(Shell("trap '' TERM; touch " + ready + "; while :; do sleep 1; done"));
  while (std::ifstream(ready).fail()) usleep(10000);  // TERM before the trap would end it
  const ExitStatus status = child.Terminate(0.2);
  EXPECT_EQ(status.signal, SIGKILL);
  EXPECT_TRUE(child.killed_after_grace());
  std::remove(ready.c_str());
}

TEST(SubprocessTest, TerminateOfAnEndedChildOnlyReapsIt) {
  Subprocess child = Subprocess::Spawn(Shell("exit 5"));
  while (!child.Poll()) usleep(1000);
  const ExitStatus status = child.Terminate(0.0);
  EXPECT_EQ(status.code, 5);
  EXPECT_FALSE(child.killed_after_grace());
}

TEST(SubprocessTest, OutputAndErrorGoToTheFile) {
  const std::string log = TestTempPath("output.log");
  { std::ofstream(log) << "old text\n"; }
  SubprocessOptions options = Shell("echo to stdout; echo to stderr >&2; echo \"[$VAR]\"");
  options.output_path = log;
  options.env["VAR"] = "added value";
  ASSERT_TRUE(Subprocess::Spawn(options).Wait().success());
  EXPECT_EQ(ReadFile(log), "to stdout\nto stderr\n[added value]\n");  // truncated first

  options.append_output = true;
  options.argv = {"/bin/sh", "-c", "echo again"};
  ASSERT_TRUE(Subprocess::Spawn(options).Wait().success());
  EXPECT_EQ(ReadFile(log), "to stdout\nto stderr\n[added value]\nagain\n");
  std::remove(log.c_str());
}

TEST(SubprocessTest, EnvironmentAdditionReplacesAnInheritedVariable) {
  ASSERT_EQ(setenv("ASLAM_SUBPROCESS_TEST", "inherited", 1), 0);
  const std::string log = TestTempPath("env.log");
  SubprocessOptions options = Shell("echo \"$ASLAM_SUBPROCESS_TEST\"; env | grep -c ^ASLAM_SUB");
  options.output_path = log;
  EXPECT_TRUE(Subprocess::Spawn(options).Wait().success());
  EXPECT_EQ(ReadFile(log), "inherited\n1\n");
  options.env["ASLAM_SUBPROCESS_TEST"] = "replaced";
  EXPECT_TRUE(Subprocess::Spawn(options).Wait().success());
  EXPECT_EQ(ReadFile(log), "replaced\n1\n");  // once, not twice
  unsetenv("ASLAM_SUBPROCESS_TEST");
  std::remove(log.c_str());
}

TEST(SubprocessTest, MissingProgramIsReportedClearly) {
  SubprocessOptions options;
  options.argv = {"/nonexistent/program", "--flag"};
  try {
    Subprocess::Spawn(options);
    FAIL() << "no error";
  } catch (const SpawnError& e) {
    EXPECT_TRUE(e.exec_failed());
    EXPECT_EQ(e.error_number(), ENOENT);
    EXPECT_EQ(std::string(e.what()), "cannot run /nonexistent/program: No such file or directory");
  }
  options.argv = {"aslam-no-such-program-on-path"};  // a bare name is looked up on PATH
  EXPECT_THROW(Subprocess::Spawn(options), SpawnError);
}

TEST(SubprocessTest, UnwritableOutputIsReportedBeforeAnyChildStarts) {
  SubprocessOptions options = Shell("exit 0");
  options.output_path = "/nonexistent/folder/out.log";
  try {
    Subprocess::Spawn(options);
    FAIL() << "no error";
  } catch (const SpawnError& e) {
    EXPECT_FALSE(e.exec_failed());
    EXPECT_NE(std::string(e.what()).find("cannot write /nonexistent/folder/out.log"),
              std::string::npos)
        << e.what();
  }
}

TEST(SubprocessTest, NoFileDescriptorLeaksIntoTheChild) {
  const int leaked = open("/dev/null", O_RDONLY);  // not close-on-exec
  ASSERT_GE(leaked, 3);
  const std::string path = "/proc/self/fd/" + std::to_string(leaked);
  // `test -e` runs in the shell itself, so /proc/self is the child.
  const ExitStatus status = Subprocess::Spawn(Shell("test -e " + path)).Wait();
  EXPECT_EQ(status.code, 1);
  close(leaked);
}

TEST(SubprocessTest, DestroyingARunningSubprocessKillsAndReapsIt) {
  pid_t pid = 0;
  {
    Subprocess child = Subprocess::Spawn(Shell("exec sleep 30"));
    pid = child.pid();
    Subprocess moved = std::move(child);  // the moved-from one owns nothing
    EXPECT_FALSE(child.running());
    EXPECT_TRUE(moved.running());
  }
  EXPECT_EQ(kill(pid, 0), -1);  // reaped, so not even a zombie is left
  EXPECT_EQ(errno, ESRCH);
}

// A group leader's leftovers die with it; here the test process is the subreaper the
// orphaned grandchild comes to (as aslam-procman is). Last: it changes the test process.
TEST(SubprocessTest, OwnGroupEndsWithItsLeaderAndReapAnyChildSeesTheRest) {
  ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  const std::string log = TestTempPath("group.log");
  SubprocessOptions options = Shell("sleep 30 & echo $!");
  options.output_path = log;
  options.own_process_group = true;
  Subprocess leader = Subprocess::Spawn(options);
  std::optional<ReapedChild> reaped;
  while (!(reaped = ReapAnyChild())) usleep(1000);
  EXPECT_EQ(reaped->pid, leader.pid());
  ASSERT_TRUE(leader.Claim(*reaped));  // also kills the group's leftovers
  EXPECT_FALSE(leader.running());
  EXPECT_EQ(leader.Poll()->code, 0);
  const pid_t grandchild = std::atoi(ReadFile(log).c_str());
  ASSERT_GT(grandchild, 0);
  int wait_status = 0;
  ASSERT_EQ(waitpid(grandchild, &wait_status, 0), grandchild);
  EXPECT_TRUE(WIFSIGNALED(wait_status) && WTERMSIG(wait_status) == SIGKILL);
  prctl(PR_SET_CHILD_SUBREAPER, 0);
  std::remove(log.c_str());
}

TEST(RunCommandTest, OutputAndExitStatusOfACommandRunToItsEnd) {
  const CommandResult result = RunCommand({"sh", "-c", "echo out; echo err >&2; exit 4"});
  EXPECT_EQ(result.status.code, 4);
  EXPECT_EQ(result.output, "out\nerr\n");
  EXPECT_TRUE(RunCommand({"true"}).status.success());
  EXPECT_THROW(RunCommand({"/no/such/program"}), SpawnError);
}

}  // namespace
}  // namespace aslam
