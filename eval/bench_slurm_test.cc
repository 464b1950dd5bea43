#include "eval/bench_slurm.h"

#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace aslam {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(SlurmArraySpecTest, TaskIdsFromZeroWithAnOptionalThrottle) {
  EXPECT_EQ(SlurmArraySpec(1, 0), "0");
  EXPECT_EQ(SlurmArraySpec(5, 0), "0-4");
  EXPECT_EQ(SlurmArraySpec(120, 8), "0-119%8");
}

TEST(SlurmJobScriptTest, OneTaskPerRunThroughBenchTask) {
  SlurmOptions slurm;
  slurm.partition = "short";
  slurm.time_limit = "20:00";
  slurm.memory = "2G";
  slurm.max_running = 4;
  const std::string script = SlurmJobScript(slurm, "/opt/aslam/build/eval/aslam",
                                            "/shared/out dir/slurm/001/run_list.tsv", 30);
  EXPECT_EQ(script.rfind("#!/bin/bash\n", 0), 0u);
  for (const std::string line :
       {"#SBATCH --job-name=aslam-bench\n", "#SBATCH --array=0-29%4\n",
        "#SBATCH --partition=short\n", "#SBATCH --time=20:00\n", "#SBATCH --mem=2G\n",
        "#SBATCH --cpus-per-task=1\n",
        // Paths quoted for the shell: a space stays inside its argument.
        "'/opt/aslam/build/eval/aslam' bench-task '/shared/out dir/slurm/001/run_list.tsv' "
        "\"$SLURM_ARRAY_TASK_ID\"\n",
        "exit \"$status\"\n"}) {
    EXPECT_THAT(script, HasSubstr(line));
  }
  // The options left empty leave the cluster's defaults.
  const std::string plain = SlurmJobScript(SlurmOptions{}, "/a'b/aslam", "/l.tsv", 1);
  EXPECT_THAT(plain, HasSubstr("#SBATCH --array=0\n"));
  EXPECT_THAT(plain, Not(HasSubstr("--partition")));
  EXPECT_THAT(plain, Not(HasSubstr("--time")));
  EXPECT_THAT(plain, Not(HasSubstr("--mem")));
  EXPECT_THAT(plain, HasSubstr("'/a'\\''b/aslam' bench-task '/l.tsv'"));
}

TEST(SlurmParseTest, SbatchJobIdAfterWarningsAndWithACluster) {
  EXPECT_EQ(ParseSbatchJobId("4711\n"), "4711");
  EXPECT_EQ(ParseSbatchJobId("sbatch: warning: can't honor --mem\n123;cluster_b\n"), "123");
  EXPECT_EQ(ParseSbatchJobId("sbatch: error: Batch job submission failed: Invalid partition\n"),
            std::nullopt);
  EXPECT_EQ(ParseSbatchJobId(""), std::nullopt);
}

TEST(SlurmParseTest, MaxArraySizeFromScontrol) {
  EXPECT_EQ(ParseMaxArraySize("MailProg                = /bin/mail\n"
                              "MaxArraySize            = 40001\n"
                              "MaxJobCount             = 10000\n"),
            40001);
  EXPECT_EQ(ParseMaxArraySize("MaxJobCount = 10000\n"), std::nullopt);
  EXPECT_EQ(ParseMaxArraySize("MaxArraySize = lots\n"), std::nullopt);
}

TEST(SlurmParseTest, SqueueArrayTasksOnly) {
  const std::vector<SlurmQueuedTask> tasks = ParseSqueueTasks(
      "812|0|RUNNING|/shared/out/slurm/001/job.sbatch\n"
      "812|1|PENDING|/shared/out/slurm/001/job.sbatch\n"
      "900|N/A|RUNNING|/home/me/other.sh\n"  // a plain job of the same user
      "garbage\n"
      "812|2|RUNNING\n"  // no script field: not squeue's answer to our format
      "813|17|COMPLETING|/a|b/job.sbatch\n");
  ASSERT_EQ(tasks.size(), 3u);
  EXPECT_EQ(tasks[0].job_id, "812");
  EXPECT_EQ(tasks[0].task, 0);
  EXPECT_EQ(tasks[0].state, "RUNNING");
  EXPECT_EQ(tasks[0].script, "/shared/out/slurm/001/job.sbatch");
  EXPECT_EQ(tasks[1].state, "PENDING");
  EXPECT_EQ(tasks[2].job_id, "813");
  EXPECT_EQ(tasks[2].task, 17);
  EXPECT_EQ(tasks[2].state, "COMPLETING");
  EXPECT_EQ(tasks[2].script, "/a|b/job.sbatch");
}

TEST(SlurmOptionsTest, BadValuesNameTheirFlag) {
  auto error_of = [](const SlurmOptions& slurm) -> std::string {
    try {
      CheckSlurmOptions(slurm);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_of(SlurmOptions{}), "");
  SlurmOptions slurm;
  slurm.partition = "a b";
  EXPECT_THAT(error_of(slurm), HasSubstr("--partition 'a b'"));
  slurm = {};
  slurm.time_limit = "1:00\n#SBATCH --x";
  EXPECT_THAT(error_of(slurm), HasSubstr("--time"));
  slurm = {};
  slurm.memory = "2G#";
  EXPECT_THAT(error_of(slurm), HasSubstr("--mem '2G#'"));
  slurm = {};
  slurm.sbatch_args = {"--account=lab", "lab2"};
  EXPECT_THAT(error_of(slurm), HasSubstr("--sbatch_args: 'lab2' is not an option"));
  slurm = {};
  slurm.max_running = -1;
  EXPECT_THAT(error_of(slurm), HasSubstr("--jobs"));
  slurm = {};
  slurm.poll_s = 0.0;
  EXPECT_THAT(error_of(slurm), HasSubstr("--slurm_poll_s 0"));
}

}  // namespace
}  // namespace aslam
