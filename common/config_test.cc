#include "common/config.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/test_temp_dir.h"

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// Runs `body` and returns the ConfigError message it throws ("" if none).
template <typename F>
std::string ErrorOf(F body) {
  try {
    body();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

struct ExampleOptions {
  double rate_hz = 10.0;
  int beams = 720;
  bool enabled = false;
  std::string name = "x";
  std::vector<double> gains = {1.0};
  double inner_m = 0.5;
};

ExampleOptions LoadExample(const ConfigReader& reader) {
  ExampleOptions options;
  reader.ReadPositive("rate_hz", &options.rate_hz);
  reader.ReadInRange("beams", &options.beams, 1, 10000);
  reader.Read("enabled", &options.enabled);
  reader.Read("name", &options.name);
  reader.Read("gains", &options.gains);
  reader.Section("inner").ReadInRange("size_m", &options.inner_m, 0.0, 2.0);
  reader.CheckAllKeysUsed();
  return options;
}

TEST(ConfigReader, ReadsValuesAndKeepsDefaults) {
  const auto options = LoadExample(ConfigReader::FromString(
      "sim:\n  rate_hz: 20\n  enabled: true\n  gains: [1, 2.5]\n  inner: {size_m: 1.5}\n", "sim"));
  EXPECT_DOUBLE_EQ(options.rate_hz, 20.0);
  EXPECT_EQ(options.beams, 720);
  EXPECT_TRUE(options.enabled);
  EXPECT_EQ(options.name, "x");
  EXPECT_EQ(options.gains, (std::vector<double>{1.0, 2.5}));
  EXPECT_DOUBLE_EQ(options.inner_m, 1.5);
}

TEST(ConfigReader, MissingSectionMeansDefaults) {
  const auto options = LoadExample(ConfigReader::FromString("nav: {}\n", "sim"));
  EXPECT_DOUBLE_EQ(options.rate_hz, 10.0);
}

TEST(ConfigReader, UnknownKeyNamesFileLineAndKey) {
  const std::string message = ErrorOf([] {
    LoadExample(ConfigReader::FromString("sim:\n  rate_hz: 5\n  beamz: 3\n", "sim", "my.yaml"));
  });
  EXPECT_THAT(message,
              AllOf(HasSubstr("my.yaml:3"), HasSubstr("sim.beamz"), HasSubstr("unknown key")));
}

TEST(ConfigReader, UnknownNestedKeyIsCaught) {
  const std::string message = ErrorOf([] {
    LoadExample(
        ConfigReader::FromString("sim:\n  inner:\n    size_m: 1\n    colour: red\n", "sim"));
  });
  EXPECT_THAT(message, HasSubstr("sim.inner.colour"));
}

TEST(ConfigReader, WrongTypeNamesKeyAndValue) {
  const std::string message = ErrorOf(
      [] { LoadExample(ConfigReader::FromString("sim:\n  beams: lots\n", "sim", "c.yaml")); });
  EXPECT_THAT(message, AllOf(HasSubstr("c.yaml:2"), HasSubstr("sim.beams"), HasSubstr("'lots'"),
                             HasSubstr("integer")));
  EXPECT_THAT(ErrorOf([] { LoadExample(ConfigReader::FromString("sim: {enabled: 3}", "sim")); }),
              HasSubstr("true or false"));
  EXPECT_THAT(ErrorOf([] { LoadExample(ConfigReader::FromString("sim: {gains: [1, a]}", "sim")); }),
              HasSubstr("sim.gains"));
  EXPECT_THAT(ErrorOf([] { LoadExample(ConfigReader::FromString("sim: {inner: 3}", "sim")); }),
              HasSubstr("expected a mapping"));
}

TEST(ConfigReader, OutOfRangeNamesKeyAndValue) {
  EXPECT_THAT(ErrorOf([] { LoadExample(ConfigReader::FromString("sim: {rate_hz: -1}", "sim")); }),
              AllOf(HasSubstr("sim.rate_hz"), HasSubstr("'-1'"), HasSubstr("positive")));
  EXPECT_THAT(ErrorOf([] { LoadExample(ConfigReader::FromString("sim: {beams: 0}", "sim")); }),
              AllOf(HasSubstr("sim.beams"), HasSubstr("[1, 10000]")));
  EXPECT_THAT(
      ErrorOf([] { LoadExample(ConfigReader::FromString("sim: {inner: {size_m: 9}}", "sim")); }),
      HasSubstr("sim.inner.size_m"));
  EXPECT_THAT(ErrorOf([] { LoadExample(ConfigReader::FromString("sim: {rate_hz: .nan}", "sim")); }),
              HasSubstr("finite"));
}

TEST(ConfigReader, NegativeValueForUnsignedIsRejected) {
  uint64_t seed = 1;
  EXPECT_THAT(
      ErrorOf([&] { ConfigReader::FromString("sim: {seed: -4}", "sim").Read("seed", &seed); }),
      HasSubstr("non-negative"));
}

TEST(ConfigReader, UnknownSectionAndMalformedYamlAreErrors) {
  EXPECT_THAT(ErrorOf([] { ConfigReader::FromString("simm: {}\n", "sim", "a.yaml"); }),
              AllOf(HasSubstr("a.yaml"), HasSubstr("unknown section 'simm'")));
  EXPECT_THAT(ErrorOf([] { ConfigReader::FromString("sim: [1, 2\n", "sim", "b.yaml"); }),
              AllOf(HasSubstr("b.yaml"), HasSubstr("malformed YAML")));
  EXPECT_THAT(ErrorOf([] { ConfigReader::FromString("sim: 3\n", "sim"); }),
              HasSubstr("must be a mapping"));
}

TEST(ConfigReader, ListsOfMappings) {
  const auto reader = ConfigReader::FromString("sim:\n  steps:\n    - {a: 1}\n    - {a: 2, b: 3}\n",
                                               "sim", "l.yaml");
  std::vector<double> values;
  for (const auto& item : reader.List("steps")) {
    double a = 0;
    item.Read("a", &a);
    values.push_back(a);
  }
  EXPECT_EQ(values, (std::vector<double>{1.0, 2.0}));
  EXPECT_THAT(ErrorOf([&] { reader.CheckAllKeysUsed(); }), HasSubstr("sim.steps[1].b"));
}

TEST(ConfigReader, FileErrorsNameTheFile) {
  EXPECT_THAT(ErrorOf([] { ConfigReader::FromFile("/nonexistent/aslam.yaml", "sim"); }),
              AllOf(HasSubstr("/nonexistent/aslam.yaml"), HasSubstr("cannot open")));
  const std::string path = TestTempPath("bad.yaml");
  {
    std::ofstream out(path);
    out << "sim:\n  rate_hz: 5\n  beams: 7.5\n";
  }
  const std::string message = ErrorOf([&] { LoadExample(ConfigReader::FromFile(path, "sim")); });
  std::filesystem::remove(path);
  EXPECT_THAT(message, AllOf(HasSubstr(path + ":3"), HasSubstr("sim.beams"), HasSubstr("'7.5'")));
}

TEST(ConfigOverride, ParsesDottedKeyAndYamlValue) {
  const ConfigOverride scalar = ParseConfigOverride("utility.hallucination.loop_closure_scale=1.5");
  EXPECT_EQ(scalar.path,
            (std::vector<std::string>{"utility", "hallucination", "loop_closure_scale"}));
  EXPECT_EQ(scalar.Key(), "utility.hallucination.loop_closure_scale");
  EXPECT_EQ(scalar.value, "1.5");
  // Split at the first '=': the value may hold one.
  EXPECT_EQ(ParseConfigOverride("a=b=c").value, "b=c");
  EXPECT_EQ(ParseConfigOverride("sim.gains=[1, 2.5]").value, "[1, 2.5]");
}

TEST(ConfigOverride, BadSyntaxNamesTheArgument) {
  EXPECT_THAT(ErrorOf([] { ParseConfigOverride("utility.lambda"); }),
              AllOf(HasSubstr("'utility.lambda'"), HasSubstr("KEY=VALUE")));
  EXPECT_THAT(ErrorOf([] { ParseConfigOverride("=0.3"); }),
              AllOf(HasSubstr("'=0.3'"), HasSubstr("empty key")));
  EXPECT_THAT(ErrorOf([] { ParseConfigOverride("utility..lambda=0.3"); }),
              AllOf(HasSubstr("'utility..lambda=0.3'"), HasSubstr("empty part")));
  EXPECT_THAT(ErrorOf([] { ParseConfigOverride("utility.=0.3"); }), HasSubstr("empty part"));
  EXPECT_THAT(ErrorOf([] { ParseConfigOverride(".lambda=0.3"); }), HasSubstr("empty part"));
  EXPECT_THAT(ErrorOf([] { ParseConfigOverride("utility.lambda="); }),
              AllOf(HasSubstr("'utility.lambda='"), HasSubstr("empty value")));
  EXPECT_THAT(ErrorOf([] { ParseConfigOverride("sim.gains=[1, 2"); }),
              AllOf(HasSubstr("'sim.gains=[1, 2'"), HasSubstr("malformed YAML")));
  EXPECT_THAT(ErrorOf([] { ParseConfigOverride("sim.inner={size_m: 1}"); }),
              HasSubstr("expected a scalar or a [flow, sequence]"));
}

// The overridden text read back: nested paths are created, existing values replaced, every
// other key kept, and no override means the file's own content.
TEST(ConfigOverride, AppliesAtNestedPathsOfAFile) {
  const std::string file = TestTempPath("override.yaml");
  std::ofstream(file) << "# a comment\nsim:\n  rate_hz: 20\n  gains: [1]\nutility:\n  "
                         "method: fd\n";
  const std::string text = ApplyConfigOverrides(
      file, {ParseConfigOverride("sim.rate_hz=5"), ParseConfigOverride("sim.gains=[3, 4.5]"),
             ParseConfigOverride("sim.inner.size_m=1.5"), ParseConfigOverride("nav.a.b.c=x"),
             ParseConfigOverride("sim.rate_hz=7")});
  const YAML::Node root = YAML::Load(text);
  EXPECT_EQ(root["sim"]["rate_hz"].as<double>(), 7.0);  // the later override wins
  EXPECT_EQ(root["sim"]["gains"].as<std::vector<double>>(), (std::vector<double>{3.0, 4.5}));
  EXPECT_EQ(root["sim"]["inner"]["size_m"].as<double>(), 1.5);
  EXPECT_EQ(root["nav"]["a"]["b"]["c"].as<std::string>(), "x");
  EXPECT_EQ(root["utility"]["method"].as<std::string>(), "fd");
  // What a component reads from it: the loaders see the overridden values.
  const auto options = LoadExample(ConfigReader::FromString(text, "sim"));
  EXPECT_DOUBLE_EQ(options.rate_hz, 7.0);
  EXPECT_EQ(options.gains, (std::vector<double>{3.0, 4.5}));
  EXPECT_DOUBLE_EQ(options.inner_m, 1.5);

  EXPECT_EQ(YAML::Load(ApplyConfigOverrides(file, {}))["sim"]["rate_hz"].as<int>(), 20);
  std::filesystem::remove(file);
}

TEST(ConfigOverride, NoFileMeansEmptyDefaults) {
  EXPECT_EQ(ApplyConfigOverrides("", {}), "{}\n");
  const YAML::Node root = YAML::Load(ApplyConfigOverrides("", {ParseConfigOverride("a.b=1")}));
  EXPECT_EQ(root.size(), 1u);
  EXPECT_EQ(root["a"]["b"].as<int>(), 1);
}

TEST(ConfigOverride, PathThroughAValueIsAnError) {
  EXPECT_THAT(ErrorOf([] {
                ApplyConfigOverrides("", {ParseConfigOverride("sim.rate_hz=5"),
                                          ParseConfigOverride("sim.rate_hz.x=1")});
              }),
              AllOf(HasSubstr("sim.rate_hz.x=1"), HasSubstr("sim.rate_hz = '5' is not a mapping")));
  EXPECT_THAT(ErrorOf([] { ApplyConfigOverrides("/nonexistent/aslam.yaml", {}); }),
              HasSubstr("/nonexistent/aslam.yaml"));
}

}  // namespace
}  // namespace aslam
