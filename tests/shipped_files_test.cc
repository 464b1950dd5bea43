// Every shipped config, drive and world loads (docs/architecture.md §7), and a drive
// shipped for a world runs through it without a collision.

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/robot_config.h"
#include "common/world_file.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/sim_config.h"
#include "drivers/sim/simulator.h"
#include "frontier/frontier_config.h"
#include "navigation/nav_config.h"
#include "slam/slam_config.h"
#include "utility/utility_config.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;
const fs::path kRoot = ASLAM_SOURCE_DIR;

std::vector<fs::path> FilesIn(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == extension) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ShippedFiles, EveryConfigLoadsEverySection) {
  const auto configs = FilesIn(kRoot / "config", ".yaml");
  ASSERT_FALSE(configs.empty());
  for (const auto& file : configs) {
    SCOPED_TRACE(file.string());
    EXPECT_NO_THROW(LoadRobotOptionsFromFile(file.string()));
    EXPECT_NO_THROW(LoadSimulatorOptionsFromFile(file.string()));
    EXPECT_NO_THROW(LoadSlamConfigFromFile(file.string()));
    EXPECT_NO_THROW(LoadNavOptionsFromFile(file.string()));
    EXPECT_NO_THROW(LoadFrontierOptionsFromFile(file.string()));
    EXPECT_NO_THROW(LoadUtilityOptionsFromFile(file.string()));
  }
}

TEST(ShippedFiles, EveryDriveLoads) {
  const auto drives = FilesIn(kRoot / "config" / "drives", ".yaml");
  ASSERT_FALSE(drives.empty());
  for (const auto& file : drives) {
    SCOPED_TRACE(file.string());
    EXPECT_GT(LoadScriptedDrive(file.string()).duration_s(), 0.0);
  }
}

TEST(ShippedFiles, EveryWorldLoadsWithAFreeStart) {
  int worlds = 0;
  for (const auto& entry : fs::directory_iterator(kRoot / "worlds")) {
    if (!entry.is_directory()) continue;
    SCOPED_TRACE(entry.path().string());
    const WorldInfo world = LoadWorld(entry.path().string());
    ASSERT_TRUE(world.has_start);
    EXPECT_GT(world.free_area_m2, 0.0);
    // The simulator refuses a start whose disc touches a wall.
    EXPECT_NO_THROW(Simulator(world.map.grid, world.start, SimulatorOptions{}));
    ++worlds;
  }
  EXPECT_GE(worlds, 3);
}

// config/drives/<world>_*.yaml is a drive through worlds/<world>: it must not
// touch a wall (noise-free odometry is irrelevant; collisions are on truth).
TEST(ShippedFiles, EveryDriveIsCollisionFreeInItsWorld) {
  for (const auto& file : FilesIn(kRoot / "config" / "drives", ".yaml")) {
    const std::string stem = file.stem().string();
    const std::string world_name = stem.substr(0, stem.find('_'));
    const fs::path world_dir = kRoot / "worlds" / world_name;
    if (!fs::exists(world_dir)) continue;
    SCOPED_TRACE(file.string());
    const WorldInfo world = LoadWorld(world_dir.string());
    Simulator simulator(world.map.grid, world.start,
                        LoadSimulatorOptionsFromFile((kRoot / "config" / "aslam.yaml").string()));
    const ScriptedDrive drive = LoadScriptedDrive(file.string());
    while (const auto command = drive.CommandAt(simulator.utime())) {
      simulator.SetCommand(*command);
      simulator.Step();
    }
    EXPECT_EQ(simulator.collisions(), 0);
  }
}

}  // namespace
}  // namespace aslam
