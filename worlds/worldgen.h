#pragma once

// Office-like floor plans for the simulator: a grid of corridors (every block
// of rooms between four corridors is a loop), rooms along them with doors,
// furniture in the rooms, scaled until the reachable free area matches a
// target, written as a world folder (loaded by common/world_file.h):
//
//   DIR/map.yaml, DIR/map.pgm   ground truth, ROS map_server format
//   DIR/world.yaml              start pose, free area, generator parameters
//   DIR/README.md               the numbers above and the command to regenerate

#include <cstdint>
#include <string>
#include <vector>

#include "common/map_io.h"
#include "common/occupancy_grid.h"
#include "common/pose2d.h"

namespace aslam {

enum class WorldStyle {
  kCampus,  // large building: long corridors, many rooms, halls, several loops
  kOffice,  // one office floor
  kTest,    // a ring corridor around one block of rooms: small, fast, one loop
  // Realistic clutter and lidar-map texture (the options in "Realistic clutter" below):
  kClutteredOffice,  // narrow doors, open-plan areas, desks, chairs, tables on legs, plants
  kWarehouse,        // wide aisles, halls of shelving rows, cluttered side rooms
};

// "campus", "office", "test", "cluttered_office" or "warehouse"; throws
// std::invalid_argument otherwise.
WorldStyle ParseWorldStyle(const std::string& text);
std::string WorldStyleName(WorldStyle style);

// Everything that shapes a world: the same options give the same map, cell
// for cell. Lengths are along a corridor (width) or across it (depth).
struct WorldgenOptions {
  WorldStyle style = WorldStyle::kOffice;
  double target_free_area_m2 = 741.0;
  uint64_t seed = 1;
  double free_area_tolerance = 0.03;  // accepted |free - target| / target

  double resolution_m = 0.05;
  double wall_thickness_m = 0.15;
  double margin_m = 1.0;  // unknown border around the building in the map
  double corridor_width_m = 1.8;
  double door_width_min_m = 1.0;
  double door_width_max_m = 1.2;
  double room_width_min_m = 3.0;
  double room_width_max_m = 5.0;
  double room_depth_min_m = 3.5;
  double room_depth_max_m = 5.0;
  double block_length_m = 16.0;  // target corridor length between two cross corridors
  double aspect_ratio = 1.5;     // building width / height
  int corridors_x = 0;           // vertical corridors, 0: chosen from the size (>= 2)
  int corridors_y = 0;           // horizontal corridors, likewise

  // Layout variety; each a probability per candidate.
  double outer_rooms_probability =
      0.5;                             // a building side gets a row of rooms outside the corridors
  double open_plan_probability = 0.2;  // a room merges with its neighbour (and gets two doors)
  double through_room_probability = 0.1;  // a room spans its block, doors on both corridors
  double side_door_probability = 0.2;     // a block's end room gets a door to the cross corridor
  double hall_probability = 0.0;          // a whole block is one open hall with four doors
  double join_blocks_probability = 0.0;  // a cross corridor segment is left out, joining two blocks
  double furniture_fill = 0.15;          // target fraction of a room's floor under furniture
  double passage_width_m = 0.9;          // furniture leaves every room passable at this width
  double room_coverage_min = 0.9;        // ... and sweepable over this share of its floor

  // Realistic clutter and texture; every default is "off" (the campus, office
  // and test styles), so those styles draw exactly as before.
  double clutter_fill = 0.0;  // > 0: cluttered furnishing, this floor share (not furniture_fill)
  double table_legs_probability = 0.0;     // a table is drawn as its four legs (what a lidar sees)
  double chairs_per_desk = 0.0;            // mean chairs beside each desk or table
  double chair_legs_probability = 0.0;     // a chair is four legs rather than a round blob
  double plants_per_100m2 = 0.0;           // small round pots along the walls of rooms
  double shelving_hall_probability = 0.0;  // a hall is filled with rows of shelving
  double hall_door_spacing_m = 0.0;        // > 0: a hall side gets a door per this length (0: one)
  double alcove_probability = 0.0;         // a room gives up a corner as a niche off the corridor
  double dead_end_probability = 0.0;       // a room gives up a strip as a dead-end corridor stub
  double corner_cut_probability = 0.0;     // a room corner is cut off by a diagonal wall
  double ragged_edge_probability = 0.0;    // share of wall faces pushed out by 1-2 cells
  double speckle_per_m2 = 0.0;             // isolated occupied cells near walls, per m2 of floor
  double robot_width_m = 0.0;  // > 0: free space a disk this wide cannot reach is filled solid
};

// The options of a style; the caller sets target area and seed.
WorldgenOptions DefaultWorldgenOptions(WorldStyle style);

// A door opening: its centre and the direction of the wall it is in.
struct DoorOpening {
  double x_m = 0.0;
  double y_m = 0.0;
  double width_m = 0.0;
  bool wall_along_x = true;
};

struct GeneratedWorld {
  OccupancyGrid grid;  // 0 free, 100 walls and furniture, -1 outside the building
  Pose2d start;        // at a corridor crossing, facing the longest free view
  double start_clearance_m = 0.0;
  double free_area_m2 = 0.0;  // free cells, all reachable from the start
  double building_width_m = 0.0;
  double building_height_m = 0.0;
  int room_count = 0;
  int corridors_x = 0;
  int corridors_y = 0;
  int loop_count = 0;                    // CountLoops(grid, kLoopObstacleMinSize_m)
  int layout_attempts = 0;               // building sizes tried to meet the target area
  std::vector<DoorOpening> doors;        // room and hall doors
  double room_floor_area_m2 = 0.0;       // rooms' floor before furniture (cluttered styles)
  double furniture_footprint_m2 = 0.0;   // floor under furniture, tables and chairs whole
  double furniture_area_m2 = 0.0;        // occupied furniture cells (a table: its legs)
  std::vector<uint8_t> furniture_cells;  // per grid cell (row-major), 1 where furniture stands
};

// Obstacles a loop must go around to count: blocks of rooms, not furniture.
constexpr double kLoopObstacleMinSize_m = 2.5;

// Throws std::invalid_argument for inconsistent options (naming the option)
// and std::runtime_error if no building size meets the area tolerance.
GeneratedWorld GenerateWorld(const WorldgenOptions& options);

// Independent cycles in the free space: obstacles enclosed by free space
// (not touching the outside) whose bounding box is at least
// `min_obstacle_size_m` on both sides.
int CountLoops(const OccupancyGrid& grid, double min_obstacle_size_m);

// The command line that regenerates a world with these options into `out_dir`.
std::string RegenerateCommand(const WorldgenOptions& options, const std::string& name,
                              const std::string& out_dir);

// Writes the world folder (creating it): map.yaml + map.pgm, world.yaml and
// README.md. Throws std::runtime_error (MapFileError for the map) on failure.
void WriteWorld(const GeneratedWorld& world, const WorldgenOptions& options,
                const std::string& name, const std::string& out_dir,
                const std::string& regenerate_command);

}  // namespace aslam
