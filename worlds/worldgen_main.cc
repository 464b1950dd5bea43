// aslam-worldgen: writes a generated world folder (map.yaml, map.pgm,
// world.yaml, README.md). Exit codes: 0 done, 1 generation or write failed,
// 2 bad command line.

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <system_error>

#include "worlds/worldgen.h"

namespace {

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

constexpr char kUsage[] =
    "Usage: aslam-worldgen --out DIR --free-area M2 --seed N [--style STYLE] [--name NAME]\n"
    "\n"
    "Generates an office-like floor plan whose free area reachable from the start\n"
    "is M2 square meters (within 3 %) and writes DIR/map.yaml, DIR/map.pgm,\n"
    "DIR/world.yaml and DIR/README.md. The same flags give the same world.\n"
    "\n"
    "  --out DIR         world folder to write (created if missing)\n"
    "  --free-area M2    target reachable free area in m^2\n"
    "  --seed N          random seed, an unsigned integer\n"
    "  --style STYLE     campus, office (default) or test\n"
    "  --name NAME       world name (default: the last folder of DIR)\n"
    "  --help            print this help\n";

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Flags {
  std::string out_dir;
  std::string name;
  aslam::WorldgenOptions options;
};

double ParsePositiveNumber(const std::string& flag, const std::string& text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !(value > 0.0)) {
    throw UsageError(flag + " expects a positive number, got '" + text + "'");
  }
  return value;
}

uint64_t ParseSeed(const std::string& text) {
  uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) {
    throw UsageError("--seed expects an unsigned integer, got '" + text + "'");
  }
  return value;
}

// Flags as `--flag value` or `--flag=value`; each at most once.
std::map<std::string, std::string> SplitFlags(int argc, char** argv) {
  static const char* const kKnown[] = {"--out", "--free-area", "--seed", "--style", "--name"};
  std::map<std::string, std::string> values;
  for (int i = 1; i < argc; ++i) {
    std::string flag = argv[i];
    std::string value;
    bool has_value = false;
    if (const auto equals = flag.find('=');
        flag.rfind("--", 0) == 0 && equals != std::string::npos) {
      value = flag.substr(equals + 1);
      flag = flag.substr(0, equals);
      has_value = true;
    }
    bool known = false;
    for (const char* name : kKnown) known = known || flag == name;
    if (!known) throw UsageError("unknown argument '" + flag + "'");
    if (!has_value) {
      if (i + 1 >= argc) throw UsageError(flag + " needs a value");
      value = argv[++i];
    }
    if (!values.emplace(flag, value).second) throw UsageError(flag + " given twice");
  }
  return values;
}

Flags ParseFlags(int argc, char** argv) {
  const std::map<std::string, std::string> values = SplitFlags(argc, argv);
  for (const char* required : {"--out", "--free-area", "--seed"}) {
    if (!values.count(required)) throw UsageError(std::string("missing ") + required);
  }
  Flags flags;
  try {
    const auto style = values.find("--style");
    flags.options = aslam::DefaultWorldgenOptions(
        style == values.end() ? aslam::WorldStyle::kOffice : aslam::ParseWorldStyle(style->second));
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--style: ") + e.what());
  }
  flags.options.target_free_area_m2 = ParsePositiveNumber("--free-area", values.at("--free-area"));
  flags.options.seed = ParseSeed(values.at("--seed"));
  flags.out_dir = values.at("--out");
  if (flags.out_dir.empty()) throw UsageError("--out needs a folder");
  const auto name = values.find("--name");
  if (name != values.end()) {
    flags.name = name->second;
  } else {
    std::filesystem::path dir = std::filesystem::path(flags.out_dir).lexically_normal();
    if (dir.filename().empty()) dir = dir.parent_path();
    flags.name = dir.filename().string();
  }
  if (flags.name.empty()) throw UsageError("--name must not be empty");
  return flags;
}

int Run(const Flags& flags) {
  const aslam::GeneratedWorld world = aslam::GenerateWorld(flags.options);
  const std::string command = aslam::RegenerateCommand(flags.options, flags.name, flags.out_dir);
  aslam::WriteWorld(world, flags.options, flags.name, flags.out_dir, command);
  std::printf(
      "%s: %.1f m2 free (target %.1f), %d x %d cells, %d rooms, %d loops, start (%.2f, %.2f, "
      "%.2f), %d layouts tried\n",
      flags.out_dir.c_str(), world.free_area_m2, flags.options.target_free_area_m2,
      world.grid.width_cells(), world.grid.height_cells(), world.room_count, world.loop_count,
      world.start.x_m, world.start.y_m, world.start.yaw_rad, world.layout_attempts);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
  }
  Flags flags;
  try {
    flags = ParseFlags(argc, argv);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "aslam-worldgen: %s\nRun 'aslam-worldgen --help' for usage.\n", e.what());
    return kExitUsage;
  }
  try {
    return Run(flags);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "aslam-worldgen: %s\n", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-worldgen: %s\n", e.what());
    return kExitFailure;
  }
}
