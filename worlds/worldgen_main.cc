// aslam-worldgen: writes a generated world folder (map.yaml, map.pgm,
// world.yaml, README.md). Exit codes: 0 done, 1 bad flags or generation
// or writing failed.

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <gflags/gflags.h>

#include "common/flags.h"

#include "worlds/worldgen.h"

DEFINE_string(out, "", "world folder to write (created if missing)");
DEFINE_double(free_area, 0.0, "target free area reachable from the start, m^2 (met within 3 %)");
DEFINE_uint64(seed, 1, "random seed: the same flags give the same world");
DEFINE_string(style, "office", "campus, office, test, cluttered_office or warehouse");
DEFINE_string(name, "", "world name (default: the last folder of --out)");

namespace aslam {
namespace {

std::string DefaultName(const std::string& out_dir) {
  std::filesystem::path dir = std::filesystem::path(out_dir).lexically_normal();
  if (dir.filename().empty()) dir = dir.parent_path();
  return dir.filename().string();
}

int Run() {
  if (FLAGS_out.empty() || !(FLAGS_free_area > 0.0)) {
    std::fprintf(
        stderr,
        "aslam-worldgen: --out and a positive --free-area are required (see --helpshort)\n");
    return 1;
  }
  try {
    WorldgenOptions options = DefaultWorldgenOptions(ParseWorldStyle(FLAGS_style));
    options.target_free_area_m2 = FLAGS_free_area;
    options.seed = FLAGS_seed;
    const std::string name = FLAGS_name.empty() ? DefaultName(FLAGS_out) : FLAGS_name;
    if (name.empty()) throw std::invalid_argument("--name must not be empty");

    const GeneratedWorld world = GenerateWorld(options);
    WriteWorld(world, options, name, FLAGS_out, RegenerateCommand(options, name, FLAGS_out));
    std::printf(
        "%s: %.1f m2 free (target %.1f), %d x %d cells, %d rooms, %d loops, start (%.2f, %.2f, "
        "%.2f), %d layouts tried\n",
        FLAGS_out.c_str(), world.free_area_m2, options.target_free_area_m2,
        world.grid.width_cells(), world.grid.height_cells(), world.room_count, world.loop_count,
        world.start.x_m, world.start.y_m, world.start.yaw_rad, world.layout_attempts);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-worldgen: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  aslam::ParseFlags(
      &argc, &argv,
      "aslam-worldgen --out DIR --free-area M2 [--seed N] [--style STYLE] [--name "
      "NAME]\n"
      "Generates an office-like floor plan and writes DIR/map.yaml, DIR/map.pgm, DIR/world.yaml\n"
      "and DIR/README.md.");
  if (argc > 1) {
    std::fprintf(stderr, "aslam-worldgen: unexpected argument '%s'\n", argv[1]);
    return 1;
  }
  return aslam::Run();
}
