#include "procman/sheriff.h"

#include <gtest/gtest.h>

namespace aslam {
namespace {

ProcessStatus Running(const std::string& name, const std::string& group, int pid, int run_id) {
  ProcessStatus p;
  p.name = name;
  p.group = group;
  p.should_run = true;
  p.state = ProcessState::kRunning;
  p.pid = pid;
  p.run_id = run_id;
  return p;
}

DeputyStatus Sample() {
  DeputyStatus d;
  d.deputy = "dep";
  d.pid = 10;
  d.processes = {Running("sim", "sim", 11, 0), Running("slam", "pipeline", 12, 3),
                 Running("nav", "pipeline", 13, 0)};
  ProcessStatus exited;
  exited.name = "once";
  exited.should_run = true;
  exited.state = ProcessState::kExited;
  exited.run_id = 2;
  d.processes.push_back(exited);
  return d;
}

const ProcessOrder& OrderOf(const DeputyOrders& orders, const std::string& name) {
  for (const auto& o : orders.processes) {
    if (o.name == name) return o;
  }
  throw std::runtime_error("no order for " + name);
}

TEST(SheriffTest, MatchesNameBeforeGroup) {
  const DeputyStatus d = Sample();
  EXPECT_EQ(MatchTargets(d, "sim"), std::vector<std::string>{"sim"});
  EXPECT_EQ(MatchTargets(d, "pipeline"), (std::vector<std::string>{"slam", "nav"}));
  EXPECT_TRUE(MatchTargets(d, "nobody").empty());
}

TEST(SheriffTest, OrdersCarryTheWholeStateWithOnlyTheTargetsChanged) {
  const DeputyStatus d = Sample();
  const DeputyOrders stop = ComputeOrders(d, SheriffCommand::kStop, MatchTargets(d, "pipeline"));
  EXPECT_EQ(stop.deputy, "dep");
  ASSERT_EQ(stop.processes.size(), 4u);
  EXPECT_TRUE(OrderOf(stop, "sim").should_run);
  EXPECT_FALSE(OrderOf(stop, "slam").should_run);
  EXPECT_EQ(OrderOf(stop, "slam").run_id, 3);  // stop never moves the run id
  EXPECT_FALSE(OrderOf(stop, "nav").should_run);
  EXPECT_EQ(OrderOf(stop, "once").run_id, 2);

  const DeputyOrders restart = ComputeOrders(d, SheriffCommand::kRestart, {"slam"});
  EXPECT_EQ(OrderOf(restart, "slam").run_id, 4);
  EXPECT_EQ(OrderOf(restart, "nav").run_id, 0);

  // start leaves a running process alone and re-runs one that has ended.
  const DeputyOrders start = ComputeOrders(d, SheriffCommand::kStart, {"sim", "once"});
  EXPECT_EQ(OrderOf(start, "sim").run_id, 0);
  EXPECT_TRUE(OrderOf(start, "once").should_run);
  EXPECT_EQ(OrderOf(start, "once").run_id, 3);
}

TEST(SheriffTest, CarriedOutOnceTheStatusShowsIt) {
  DeputyStatus d = Sample();
  const DeputyOrders stop = ComputeOrders(d, SheriffCommand::kStop, {"nav"});
  EXPECT_FALSE(OrdersCarriedOut(d, stop));
  d.processes[2].should_run = false;
  d.processes[2].state = ProcessState::kStopping;
  EXPECT_FALSE(OrdersCarriedOut(d, stop));
  d.processes[2].state = ProcessState::kStopped;
  d.processes[2].pid = 0;
  EXPECT_TRUE(OrdersCarriedOut(d, stop));

  const DeputyOrders restart = ComputeOrders(d, SheriffCommand::kRestart, {"slam"});
  EXPECT_FALSE(OrdersCarriedOut(d, restart));
  d.processes[1].run_id = 4;
  d.processes[1].pid = 99;
  EXPECT_TRUE(OrdersCarriedOut(d, restart));
}

TEST(SheriffTest, TableShowsEveryColumn) {
  DeputyStatus d = Sample();
  d.processes[1].restarts = 2;
  d.processes[1].exit_code = -9;
  d.processes[1].cpu_percent = 12.5;
  d.processes[1].rss_bytes = 25'000'000;
  const std::string table = FormatStatusTable({d});
  EXPECT_NE(table.find("deputy dep (pid 10)"), std::string::npos) << table;
  EXPECT_NE(table.find("name"), std::string::npos);
  EXPECT_NE(table.find("rss_MB"), std::string::npos);
  EXPECT_NE(
      table.find(
          "slam             pipeline     running         12        2    -9    12.5      25.0"),
      std::string::npos)
      << table;
  EXPECT_NE(table.find("once             -            exited"), std::string::npos) << table;
}

TEST(SheriffTest, ParsesCommands) {
  SheriffCommand c;
  EXPECT_TRUE(ParseSheriffCommand("restart", &c));
  EXPECT_EQ(c, SheriffCommand::kRestart);
  EXPECT_FALSE(ParseSheriffCommand("kill", &c));
}

}  // namespace
}  // namespace aslam
