#include "eval/bench_settings.h"

#include <filesystem>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/test_temp_dir.h"
#include "eval/bench_testing.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

std::vector<std::string> Labels(const std::vector<BenchSetting>& settings) {
  std::vector<std::string> labels;
  for (const BenchSetting& s : settings) labels.push_back(s.label);
  return labels;
}

// The message of the exception `body` throws ("no error" if none).
template <typename F>
std::string ErrorOf(F body) {
  try {
    body();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

TEST(SplitSweepValuesTest, CommasOutsideBracketsAndQuotes) {
  EXPECT_EQ(SplitSweepValues("0.3,0.6, 1.2"), (std::vector<std::string>{"0.3", "0.6", "1.2"}));
  EXPECT_EQ(SplitSweepValues("[1, 2],[3,4]"), (std::vector<std::string>{"[1, 2]", "[3,4]"}));
  EXPECT_EQ(SplitSweepValues("'a,b',\"c,d\""), (std::vector<std::string>{"'a,b'", "\"c,d\""}));
  EXPECT_EQ(SplitSweepValues("x"), (std::vector<std::string>{"x"}));
  EXPECT_EQ(SplitSweepValues("1,,2"), (std::vector<std::string>{"1", "", "2"}));
  EXPECT_TRUE(SplitSweepValues("").empty());
}

TEST(PlanSettingsTest, NoSweepIsOneUnlabelledSetting) {
  const std::vector<BenchSetting> settings = PlanSettings({});
  ASSERT_EQ(settings.size(), 1u);
  EXPECT_EQ(settings[0].label, "");
  EXPECT_TRUE(settings[0].overrides.empty());
}

TEST(PlanSettingsTest, CartesianProductFirstSetSlowest) {
  const std::vector<BenchSetting> settings =
      PlanSettings({"utility.lambda=0.3,0.6,1.2", "nav.goal_snap_m=0.1,0.2"});
  EXPECT_EQ(
      Labels(settings),
      (std::vector<std::string>{
          "utility.lambda=0.3+nav.goal_snap_m=0.1", "utility.lambda=0.3+nav.goal_snap_m=0.2",
          "utility.lambda=0.6+nav.goal_snap_m=0.1", "utility.lambda=0.6+nav.goal_snap_m=0.2",
          "utility.lambda=1.2+nav.goal_snap_m=0.1", "utility.lambda=1.2+nav.goal_snap_m=0.2"}));
  ASSERT_EQ(settings[3].overrides.size(), 2u);
  EXPECT_EQ(settings[3].overrides[0].Key(), "utility.lambda");
  EXPECT_EQ(settings[3].overrides[0].value, "0.6");
  EXPECT_EQ(settings[3].overrides[1].Key(), "nav.goal_snap_m");
  EXPECT_EQ(settings[3].overrides[1].value, "0.2");
}

TEST(PlanSettingsTest, LabelsAreOneFolderName) {
  EXPECT_EQ(Labels(PlanSettings({"slam.x=[1, 2],[3,4]"})),
            (std::vector<std::string>{"slam.x=[1,_2]", "slam.x=[3,4]"}));
  EXPECT_EQ(Labels(PlanSettings({"utility.distance_unit=m/s"})),
            (std::vector<std::string>{"utility.distance_unit=m_s"}));
  for (const std::string& label : Labels(PlanSettings({"slam.x=a b,c/d"}))) {
    EXPECT_EQ(label.find_first_of("/ "), std::string::npos) << label;
  }
}

TEST(PlanSettingsTest, BadSweepsNameTheSet) {
  EXPECT_THAT(ErrorOf([] { PlanSettings({"utility.lambda"}); }),
              AllOf(HasSubstr("'utility.lambda'"), HasSubstr("KEY=VALUE")));
  EXPECT_THAT(ErrorOf([] { PlanSettings({"utility.lambda="}); }), HasSubstr("empty value"));
  EXPECT_THAT(ErrorOf([] { PlanSettings({"utility.lambda=0.3,,0.6"}); }),
              AllOf(HasSubstr("empty value"), HasSubstr("in --set 'utility.lambda=0.3,,0.6'")));
  EXPECT_THAT(ErrorOf([] { PlanSettings({"utility..lambda=1"}); }), HasSubstr("empty part"));
  EXPECT_THAT(ErrorOf([] {
                PlanSettings({"utility.lambda=1", "utility.lambda=2"});
              }),
              HasSubstr("utility.lambda is given twice"));
  EXPECT_THAT(ErrorOf([] { PlanSettings({"utility.lambda=1,1"}); }),
              HasSubstr("two settings are labelled 'utility.lambda=1'"));
  EXPECT_THAT(ErrorOf([] { PlanSettings({"utility.method=fd,ours"}); }), HasSubstr("--methods"));
  EXPECT_THAT(ErrorOf([] { PlanSettings({"sim.seed=3"}); }), HasSubstr("--seeds"));
  EXPECT_THAT(ErrorOf([] { PlanSettings({"eval.x=3"}); }),
              AllOf(HasSubstr("'eval.x=3'"), HasSubstr("section 'eval'")));
  EXPECT_EQ(ErrorOf([] { PlanSettings({"utility.hallucination.loop_closure_scale=1,2"}); }),
            "no error");
}

TEST(WriteSettingConfigsTest, EachSettingsConfigHoldsItsOverrides) {
  const std::string out = FreshTestTempDir("setting_configs");
  const std::string shipped = std::string(ASLAM_SOURCE_DIR) + "/config/aslam.yaml";
  const std::vector<BenchSetting> settings = PlanSettings({"utility.lambda=0.3,1.2"});
  WriteSettingConfigs(shipped, settings, out);
  const YAML::Node low = YAML::LoadFile(SettingConfigPath(out, "utility.lambda=0.3"));
  const YAML::Node high = YAML::LoadFile(out + "/settings/utility.lambda=1.2/config.yaml");
  EXPECT_EQ(low["utility"]["lambda"].as<double>(), 0.3);
  EXPECT_EQ(high["utility"]["lambda"].as<double>(), 1.2);
  // The rest is the base config's.
  EXPECT_EQ(high["utility"]["method"].as<std::string>(),
            YAML::LoadFile(shipped)["utility"]["method"].as<std::string>());
  EXPECT_EQ(high["slam"].size(), YAML::LoadFile(shipped)["slam"].size());
  // Nothing is written for a bench without --set.
  const std::string plain = FreshTestTempDir("setting_configs_plain");
  WriteSettingConfigs(shipped, PlanSettings({}), plain);
  EXPECT_FALSE(fs::exists(plain + "/settings"));
}

TEST(WriteSettingConfigsTest, MisspeltKeyFailsBeforeAnyRunNamingIt) {
  const std::string out = FreshTestTempDir("setting_typo");
  EXPECT_THAT(ErrorOf([&] { WriteSettingConfigs("", PlanSettings({"utility.lamda=1"}), out); }),
              AllOf(HasSubstr("utility.lamda"), HasSubstr("unknown key"),
                    HasSubstr("settings/utility.lamda=1/config.yaml")));
  EXPECT_THAT(ErrorOf([&] { WriteSettingConfigs("", PlanSettings({"utility.lambda=-1"}), out); }),
              AllOf(HasSubstr("utility.lambda"), HasSubstr("'-1'")));
}

// A resumed sweep may not run a setting's remaining runs under another config than its first.
TEST(WriteSettingConfigsTest, ChangedBaseConfigWithRunsIsRefused) {
  const std::string out = FreshTestTempDir("setting_changed");
  const std::string base = out + "/base.yaml";
  WriteFile(base, "nav:\n  goal_snap_m: 0.15\n");
  const std::vector<BenchSetting> settings = PlanSettings({"utility.lambda=0.3"});
  WriteSettingConfigs(base, settings, out);
  WriteSettingConfigs(base, settings, out);  // the same again: fine
  WriteFile(base, "nav:\n  goal_snap_m: 0.2\n");
  WriteSettingConfigs(base, settings, out);  // no runs yet: rewritten
  EXPECT_EQ(YAML::LoadFile(SettingConfigPath(out, "utility.lambda=0.3"))["nav"]["goal_snap_m"]
                .as<double>(),
            0.2);
  fs::create_directories(out + "/runs/utility.lambda=0.3/test/fd/seed_01");
  WriteFile(base, "nav:\n  goal_snap_m: 0.25\n");
  EXPECT_THAT(ErrorOf([&] { WriteSettingConfigs(base, settings, out); }),
              AllOf(HasSubstr("settings/utility.lambda=0.3/config.yaml differs"),
                    HasSubstr("runs/utility.lambda=0.3")));
}

}  // namespace
}  // namespace aslam
