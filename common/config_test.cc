#include "common/config.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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
  const auto path = std::filesystem::temp_directory_path() / "aslam_config_test_bad.yaml";
  {
    std::ofstream out(path);
    out << "sim:\n  rate_hz: 5\n  beams: 7.5\n";
  }
  const std::string message =
      ErrorOf([&] { LoadExample(ConfigReader::FromFile(path.string(), "sim")); });
  std::filesystem::remove(path);
  EXPECT_THAT(message,
              AllOf(HasSubstr(path.string() + ":3"), HasSubstr("sim.beams"), HasSubstr("'7.5'")));
}

}  // namespace
}  // namespace aslam
