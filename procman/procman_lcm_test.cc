#include "procman/procman_lcm.h"

#include <gtest/gtest.h>

namespace aslam {
namespace {

TEST(ProcmanLcmTest, StatusRoundTripsWithEveryField) {
  DeputyStatus status;
  status.deputy = "dep";
  status.pid = 42;
  ProcessStatus p;
  p.name = "slam";
  p.group = "pipeline";
  p.command_line = "aslam-slam --config c.yaml";
  p.should_run = true;
  p.state = ProcessState::kBackoff;
  p.pid = 0;
  p.exit_code = -9;
  p.restarts = 3;
  p.run_id = 2;
  p.cpu_percent = 55.5;
  p.rss_bytes = 123456789;
  p.uptime_s = 7.5;
  status.processes = {p};
  const procman_status_t message = ToLcm(status, 1234);
  EXPECT_EQ(message.utime, 1234);
  EXPECT_EQ(message.num_processes, 1);
  EXPECT_EQ(message.processes[0].state, procman_process_status_t::STATE_BACKOFF);
  // Through the wire format, as the sheriff gets it.
  std::vector<uint8_t> bytes(message.getEncodedSize());
  ASSERT_EQ(message.encode(bytes.data(), 0, bytes.size()), static_cast<int>(bytes.size()));
  procman_status_t decoded;
  ASSERT_EQ(decoded.decode(bytes.data(), 0, bytes.size()), static_cast<int>(bytes.size()));
  DeputyStatus back;
  ASSERT_TRUE(FromLcm(decoded, &back));
  EXPECT_EQ(back.deputy, "dep");
  EXPECT_EQ(back.pid, 42);
  ASSERT_EQ(back.processes.size(), 1u);
  const ProcessStatus& q = back.processes[0];
  EXPECT_EQ(q.name, "slam");
  EXPECT_EQ(q.group, "pipeline");
  EXPECT_EQ(q.command_line, p.command_line);
  EXPECT_TRUE(q.should_run);
  EXPECT_EQ(q.state, ProcessState::kBackoff);
  EXPECT_EQ(q.exit_code, -9);
  EXPECT_EQ(q.restarts, 3);
  EXPECT_EQ(q.run_id, 2);
  EXPECT_EQ(q.cpu_percent, 55.5);
  EXPECT_EQ(q.rss_bytes, 123456789);
  EXPECT_EQ(q.uptime_s, 7.5);
}

TEST(ProcmanLcmTest, ExitedTravelsAsItsOwnState) {
  DeputyStatus status;
  ProcessStatus p;
  p.name = "sim";
  p.should_run = true;
  p.state = ProcessState::kExited;
  status.processes = {p};
  const procman_status_t message = ToLcm(status, 0);
  EXPECT_EQ(message.processes[0].state, procman_process_status_t::STATE_EXITED);
  DeputyStatus back;
  ASSERT_TRUE(FromLcm(message, &back));
  EXPECT_EQ(back.processes[0].state, ProcessState::kExited);
}

// STATE_EXITED is a constant, which the type's hash leaves out: PROCMAN_STATUS in logs recorded
// before it still decodes. The hash as lcm-gen computed it before the constant was added:
TEST(ProcmanLcmTest, TheStatusTypeKeepsItsHash) {
  const uint64_t base = 0x1aaee1fb81b70506ULL;
  EXPECT_EQ(static_cast<uint64_t>(procman_process_status_t::getHash()),
            (base << 1) + ((base >> 63) & 1));
}

TEST(ProcmanLcmTest, OrdersRoundTripAndBadOnesAreRefused) {
  const DeputyOrders orders{"dep", {{"a", true, 3}, {"b", false, 0}}};
  const procman_orders_t message = ToLcm(orders, 99, "sheriff-1");
  EXPECT_EQ(message.sheriff, "sheriff-1");
  EXPECT_EQ(message.num_processes, 2);
  DeputyOrders back;
  ASSERT_TRUE(FromLcm(message, &back));
  EXPECT_EQ(back.deputy, "dep");
  ASSERT_EQ(back.processes.size(), 2u);
  EXPECT_EQ(back.processes[0].name, "a");
  EXPECT_TRUE(back.processes[0].should_run);
  EXPECT_EQ(back.processes[0].run_id, 3);
  EXPECT_FALSE(back.processes[1].should_run);

  procman_orders_t bad = message;
  bad.num_processes = 3;
  EXPECT_FALSE(FromLcm(bad, &back));
  bad = message;
  bad.processes[1].name = "";
  EXPECT_FALSE(FromLcm(bad, &back));

  procman_status_t bad_status = ToLcm(DeputyStatus{}, 0);
  bad_status.num_processes = 1;
  DeputyStatus status;
  EXPECT_FALSE(FromLcm(bad_status, &status));
}

}  // namespace
}  // namespace aslam
