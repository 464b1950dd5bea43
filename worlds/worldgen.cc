#include "worlds/worldgen.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace aslam {
namespace {

namespace fs = std::filesystem;

// Cell labels while drawing; walls and furniture both become occupied.
constexpr uint8_t kOutsideLabel = 0;
constexpr uint8_t kWallLabel = 1;
constexpr uint8_t kFurnitureLabel = 2;
constexpr uint8_t kFreeLabel = 3;

// Furniture must leave every room passable for a disk of this radius (a
// 0.9 m wide robot path) and let it sweep most of the floor.
constexpr double kPassageRadius_m = 0.45;
constexpr double kMinRoomCoverage = 0.9;
constexpr double kDoorKeepClearDepth_m = 1.2;  // furniture-free zone inside a door
constexpr double kDoorKeepClearSide_m = 0.3;
constexpr double kDoorInset_m = 0.2;        // wall kept between a door and a room corner
constexpr double kSnapGap_m = 0.9;          // gaps between furniture below this close up
constexpr double kIslandClearance_m = 1.0;  // free ring around a table in the open
constexpr double kStartClearanceMin_m = 0.6;
constexpr double kExpectedFreeFraction = 0.72;  // free / building area, first size guess
constexpr double kSearchGoal = 0.005;           // stop searching sizes this close to the target
constexpr int kMaxLayoutAttempts = 30;
constexpr int kFurnitureAttemptsPerRoom = 30;

// Portable draws: the engine's output sequence is fixed by the standard, the
// <random> distributions are not, so the draws are derived here.
class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}

  // Uniform in [lo, hi], lo <= hi; rejection keeps it free of modulo bias.
  int Int(int lo, int hi) {
    const uint64_t span = static_cast<uint64_t>(static_cast<int64_t>(hi) - lo) + 1;
    const uint64_t max = std::numeric_limits<uint64_t>::max();
    const uint64_t limit = max - max % span;
    uint64_t draw = engine_();
    while (draw >= limit) draw = engine_();
    return static_cast<int>(lo + static_cast<int64_t>(draw % span));
  }
  // Uniform in [0, 1) from the top 53 bits.
  double Unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double Real(double lo, double hi) { return lo + (hi - lo) * Unit(); }
  bool Chance(double probability) { return Unit() < probability; }

 private:
  std::mt19937_64 engine_;
};

int ToCells(double length_m, double resolution_m) {
  return static_cast<int>(std::lround(length_m / resolution_m));
}

// The option lengths in cells.
struct CellSizes {
  explicit CellSizes(const WorldgenOptions& options)
      : resolution_m(options.resolution_m),
        wall(Cells(options.wall_thickness_m)),
        margin(Cells(options.margin_m)),
        corridor(Cells(options.corridor_width_m)),
        door_min(Cells(options.door_width_min_m)),
        door_max(Cells(options.door_width_max_m)),
        door_inset(Cells(kDoorInset_m)),
        width_min(Cells(options.room_width_min_m)),
        width_max(Cells(options.room_width_max_m)),
        depth_min(Cells(options.room_depth_min_m)),
        depth_max(Cells(options.room_depth_max_m)),
        block_length(Cells(options.block_length_m)) {}

  int Cells(double length_m) const { return ToCells(length_m, resolution_m); }
  double Meters(int cells) const { return cells * resolution_m; }
  double SquareMeters(double cells) const { return cells * resolution_m * resolution_m; }

  double resolution_m;
  int wall, margin, corridor, door_min, door_max, door_inset;
  int width_min, width_max, depth_min, depth_max, block_length;
};

struct Interval {
  int start = 0;
  int size = 0;
  int end() const { return start + size; }
};

enum class Side { kBottom, kTop, kLeft, kRight };

bool RunsAlongX(Side side) { return side == Side::kBottom || side == Side::kTop; }

// A rectangle given by its extent along a row's axis and across it.
cv::Rect RowRect(bool along_x, Interval along, Interval across) {
  return along_x ? cv::Rect(along.start, across.start, along.size, across.size)
                 : cv::Rect(across.start, along.start, across.size, along.size);
}

Interval AlongInterval(const cv::Rect& rect, bool along_x) {
  return along_x ? Interval{rect.x, rect.width} : Interval{rect.y, rect.height};
}

struct Door {
  cv::Rect opening;  // the wall cells carved out
  Side side;         // the room wall it is in
};

enum class RoomKind { kOffice, kMeeting, kOpenPlan, kLab, kHall };

struct Room {
  cv::Rect interior;
  std::vector<Door> doors;
  RoomKind kind = RoomKind::kOffice;
};

struct Layout {
  cv::Size canvas;
  cv::Rect building;  // outer faces of the outer walls
  std::vector<cv::Rect> corridors;
  std::vector<cv::Point> crossings;  // centre cells of corridor crossings
  std::vector<Room> rooms;
  int corridors_x = 0;
  int corridors_y = 0;
};

// `count` sizes summing to `total`, each at least `min_size`, the rest
// shared by weights drawn in [1 - jitter, 1 + jitter].
std::vector<int> JitteredSizes(int total, int count, int min_size, double jitter, Rng& rng) {
  std::vector<double> weights(count);
  double weight_sum = 0.0;
  for (double& weight : weights) {
    weight = rng.Real(1.0 - jitter, 1.0 + jitter);
    weight_sum += weight;
  }
  const int extra = total - count * min_size;
  std::vector<int> sizes(count);
  double cumulative = 0.0;
  int given = 0;
  for (int i = 0; i < count; ++i) {
    cumulative += weights[i];
    const int until = i + 1 == count ? extra : static_cast<int>(extra * cumulative / weight_sum);
    sizes[i] = min_size + until - given;
    given = until;
  }
  return sizes;
}

// Splits `span` into pieces of about `mean` cells (at least `min_size`)
// separated by walls.
std::vector<Interval> SplitIntoSegments(Interval span, int mean, int min_size, int wall, Rng& rng) {
  int count = std::max(1, static_cast<int>(std::lround(double(span.size + wall) / (mean + wall))));
  while (count > 1 && span.size - (count - 1) * wall < count * min_size) --count;
  const int usable = span.size - (count - 1) * wall;
  const std::vector<int> sizes =
      JitteredSizes(usable, count, std::min(min_size, usable / count), 0.5, rng);
  std::vector<Interval> segments;
  int position = span.start;
  for (int size : sizes) {
    segments.push_back({position, size});
    position += size + wall;
  }
  return segments;
}

// The along-wall cells of a room wall where a door may go.
Interval DoorSpan(Interval room_along, Interval corridor_along) {
  const int start = std::max(room_along.start, corridor_along.start);
  const int end = std::min(room_along.end(), corridor_along.end());
  return {start, std::max(0, end - start)};
}

bool DoorFits(Interval span, const CellSizes& cells) {
  return span.size >= cells.door_min + 2 * cells.door_inset;
}

// A door in the `side` wall of `interior` within `span` (along that wall).
std::optional<Door> PlaceDoor(const cv::Rect& interior, Side side, Interval span, int width_min,
                              int width_max, const CellSizes& cells, Rng& rng) {
  const int room_for_door = span.size - 2 * cells.door_inset;
  if (room_for_door < width_min) return std::nullopt;
  const int width = rng.Int(width_min, std::min(width_max, room_for_door));
  const int first = span.start + cells.door_inset;
  const int last = span.end() - cells.door_inset - width;
  // Office doors sit near a corner more often than in the middle.
  const int slack = std::min(last - first, cells.Cells(0.5));
  int position = rng.Int(first, last);
  const double style = rng.Unit();
  if (style < 0.35) {
    position = first + rng.Int(0, slack);
  } else if (style < 0.7) {
    position = last - rng.Int(0, slack);
  }
  cv::Rect opening;
  switch (side) {
    case Side::kBottom: opening = {position, interior.y - cells.wall, width, cells.wall}; break;
    case Side::kTop: opening = {position, interior.y + interior.height, width, cells.wall}; break;
    case Side::kLeft: opening = {interior.x - cells.wall, position, cells.wall, width}; break;
    case Side::kRight: opening = {interior.x + interior.width, position, cells.wall, width}; break;
  }
  return Door{opening, side};
}

RoomKind ChooseRoomKind(double area_m2, bool merged, Rng& rng) {
  const double draw = rng.Unit();
  if (merged) return draw < 0.7 ? RoomKind::kOpenPlan : RoomKind::kLab;
  if (area_m2 < 22.0) return draw < 0.8 ? RoomKind::kOffice : RoomKind::kMeeting;
  if (area_m2 < 40.0) {
    return draw < 0.4 ? RoomKind::kOffice : draw < 0.7 ? RoomKind::kMeeting : RoomKind::kLab;
  }
  return draw < 0.5 ? RoomKind::kOpenPlan : draw < 0.8 ? RoomKind::kLab : RoomKind::kMeeting;
}

// A row of rooms side by side, doors in walls that have a corridor behind them.
struct RowSpec {
  bool along_x = true;
  Interval across;               // the rooms' depth
  std::vector<Side> door_sides;  // walls facing a corridor
  bool one_door_side = false;    // each room picks one of door_sides (unless a through room)
  Interval corridor_along;       // where those walls face the corridor
};

void AddRoomRow(const std::vector<Interval>& segments, const RowSpec& row,
                const WorldgenOptions& options, const CellSizes& cells, Rng& rng,
                std::vector<Room>* rooms) {
  // Group segments into rooms: a room needs a door span; some merge (open plan).
  std::vector<std::pair<int, int>> groups;
  const int count = static_cast<int>(segments.size());
  auto span_of = [&](int first, int last) {
    return DoorSpan({segments[first].start, segments[last].end() - segments[first].start},
                    row.corridor_along);
  };
  for (int first = 0; first < count;) {
    int last = first;
    while (!DoorFits(span_of(first, last), cells) && last + 1 < count) ++last;
    while (last + 1 < count && last - first < 2 && rng.Chance(options.open_plan_probability)) {
      ++last;
    }
    groups.emplace_back(first, last);
    first = last + 1;
  }
  if (groups.size() > 1 && !DoorFits(span_of(groups.back().first, groups.back().second), cells)) {
    groups[groups.size() - 2].second = groups.back().second;
    groups.pop_back();
  }

  for (const auto& [first, last] : groups) {
    Room room;
    const Interval along{segments[first].start, segments[last].end() - segments[first].start};
    room.interior = RowRect(row.along_x, along, row.across);
    const bool merged = last > first;
    room.kind = ChooseRoomKind(cells.SquareMeters(room.interior.area()), merged, rng);

    std::vector<Side> sides = row.door_sides;
    if (row.one_door_side && sides.size() > 1 && !rng.Chance(options.through_room_probability)) {
      sides = {sides[rng.Int(0, static_cast<int>(sides.size()) - 1)]};
    }
    const Interval span = span_of(first, last);
    for (Side side : sides) {
      // Merged rooms get a door in each half of their wall.
      const int halves = merged && span.size >= 2 * (cells.door_max + 2 * cells.door_inset) ? 2 : 1;
      for (int half = 0; half < halves; ++half) {
        const Interval part{span.start + half * span.size / halves, span.size / halves};
        if (auto door =
                PlaceDoor(room.interior, side, part, cells.door_min, cells.door_max, cells, rng)) {
          room.doors.push_back(*door);
        }
      }
    }
    if (!room.doors.empty()) rooms->push_back(room);
  }
}

// The rooms of a block enclosed by corridors on all four sides.
void AddBlockRooms(const cv::Rect& interior, const WorldgenOptions& options, const CellSizes& cells,
                   Rng& rng, std::vector<Room>* rooms) {
  const double area_m2 = cells.SquareMeters(interior.area());
  if (area_m2 >= 80.0 && rng.Chance(options.hall_probability)) {
    Room hall;
    hall.interior = interior;
    hall.kind = RoomKind::kHall;
    for (Side side : {Side::kBottom, Side::kTop, Side::kLeft, Side::kRight}) {
      const Interval along = AlongInterval(interior, RunsAlongX(side));
      const Interval middle{along.start + along.size / 5, along.size * 3 / 5};
      if (auto door = PlaceDoor(interior, side, middle, 2 * cells.door_min, 2 * cells.door_max,
                                cells, rng)) {
        hall.doors.push_back(*door);
      }
    }
    rooms->push_back(hall);
    return;
  }

  const Interval along{interior.x, interior.width};
  const int mean_width = (cells.width_min + cells.width_max) / 2;
  const std::vector<Interval> segments =
      SplitIntoSegments(along, mean_width, cells.width_min, cells.wall, rng);
  const std::size_t first_room = rooms->size();

  if (interior.height >= 2 * cells.depth_min + cells.wall) {
    // Double-loaded: a row facing each corridor, some rooms spanning both.
    const int usable = interior.height - cells.wall;
    const int bottom_depth = std::clamp(static_cast<int>(std::lround(usable * rng.Real(0.4, 0.6))),
                                        cells.depth_min, usable - cells.depth_min);
    const Interval bottom{interior.y, bottom_depth};
    const Interval top{interior.y + bottom_depth + cells.wall, usable - bottom_depth};
    std::vector<bool> through(segments.size());
    for (std::size_t i = 0; i < segments.size(); ++i) {
      through[i] = rng.Chance(options.through_room_probability);
    }
    for (std::size_t i = 0; i < segments.size();) {
      if (through[i]) {
        AddRoomRow({segments[i]},
                   {true, {interior.y, interior.height}, {Side::kBottom, Side::kTop}, false, along},
                   options, cells, rng, rooms);
        ++i;
        continue;
      }
      std::vector<Interval> run;
      for (; i < segments.size() && !through[i]; ++i) run.push_back(segments[i]);
      AddRoomRow(run, {true, bottom, {Side::kBottom}, false, along}, options, cells, rng, rooms);
      AddRoomRow(run, {true, top, {Side::kTop}, false, along}, options, cells, rng, rooms);
    }
  } else {
    AddRoomRow(segments,
               {true, {interior.y, interior.height}, {Side::kBottom, Side::kTop}, true, along},
               options, cells, rng, rooms);
  }

  // End rooms may also open onto the cross corridor beside them.
  for (std::size_t i = first_room; i < rooms->size(); ++i) {
    Room& room = (*rooms)[i];
    const Interval side_span{room.interior.y, room.interior.height};
    if (room.interior.x == interior.x && rng.Chance(options.side_door_probability)) {
      if (auto door = PlaceDoor(room.interior, Side::kLeft, side_span, cells.door_min,
                                cells.door_max, cells, rng)) {
        room.doors.push_back(*door);
      }
    }
    if (room.interior.x + room.interior.width == interior.x + interior.width &&
        rng.Chance(options.side_door_probability)) {
      if (auto door = PlaceDoor(room.interior, Side::kRight, side_span, cells.door_min,
                                cells.door_max, cells, rng)) {
        room.doors.push_back(*door);
      }
    }
  }
}

// Block sizes between `count` corridors across `span` cells; empty if they
// cannot hold a room of `min_interior` cells.
std::vector<int> BlockSizes(int span, int count, int min_interior, const CellSizes& cells,
                            Rng& rng) {
  const int min_block = min_interior + 2 * cells.wall;
  const int total = span - count * cells.corridor;
  if (total < (count - 1) * min_block) return {};
  return JitteredSizes(total, count - 1, min_block, 0.25, rng);
}

int CorridorCount(int forced, int span, int block_target, const CellSizes& cells) {
  if (forced > 0) return forced;
  const double blocks = double(span - cells.corridor) / (block_target + cells.corridor);
  return std::max(2, static_cast<int>(std::lround(blocks)) + 1);
}

// The floor plan of a building of `width` x `height` cells; nullopt if it is
// too small for the style.
std::optional<Layout> MakeLayout(int width, int height, const WorldgenOptions& options,
                                 const CellSizes& cells, Rng& rng) {
  Layout layout;
  const int wall = cells.wall;
  layout.building = {cells.margin, cells.margin, width, height};
  layout.canvas = {width + 2 * cells.margin, height + 2 * cells.margin};
  const int x0 = layout.building.x, y0 = layout.building.y;

  // Rows of rooms outside the corridor grid, per side: left, right, bottom, top.
  std::array<int, 4> strip_depth{};
  for (int& depth : strip_depth) {
    const bool has_strip = rng.Chance(options.outer_rooms_probability);
    const int drawn = rng.Int(cells.depth_min, cells.depth_max);
    depth = has_strip ? drawn : 0;
  }
  const auto strip_extent = [&](int side) {
    return strip_depth[side] ? strip_depth[side] + wall : 0;
  };
  const int grid_x0 = x0 + wall + strip_extent(0);
  const int grid_x1 = x0 + width - wall - strip_extent(1);
  const int grid_y0 = y0 + wall + strip_extent(2);
  const int grid_y1 = y0 + height - wall - strip_extent(3);
  const int grid_width = grid_x1 - grid_x0;
  const int grid_height = grid_y1 - grid_y0;
  if (grid_width <= 0 || grid_height <= 0) return std::nullopt;

  const int block_depth_target = cells.depth_min + cells.depth_max + 3 * wall;
  int count_x = CorridorCount(options.corridors_x, grid_width, cells.block_length, cells);
  int count_y = CorridorCount(options.corridors_y, grid_height, block_depth_target, cells);
  std::vector<int> block_widths, block_heights;
  for (; count_x >= 2; --count_x) {
    block_widths = BlockSizes(grid_width, count_x, cells.width_min, cells, rng);
    if (!block_widths.empty() || options.corridors_x > 0) break;
  }
  for (; count_y >= 2; --count_y) {
    block_heights = BlockSizes(grid_height, count_y, cells.depth_min, cells, rng);
    if (!block_heights.empty() || options.corridors_y > 0) break;
  }
  if (block_widths.empty() || block_heights.empty()) return std::nullopt;
  layout.corridors_x = count_x;
  layout.corridors_y = count_y;

  std::vector<int> corridor_x{grid_x0}, corridor_y{grid_y0};
  for (int size : block_widths) corridor_x.push_back(corridor_x.back() + cells.corridor + size);
  for (int size : block_heights) corridor_y.push_back(corridor_y.back() + cells.corridor + size);
  // Some segments of inner cross corridors are left out, joining the two
  // blocks beside them into one long block (T junctions, one loop fewer).
  const int blocks_x = count_x - 1, blocks_y = count_y - 1;
  std::vector<bool> joined_right(blocks_x * blocks_y, false);  // block joins its right neighbour
  std::vector<bool> in_pair(blocks_x * blocks_y, false);
  for (int j = 0; j < blocks_y; ++j) {
    for (int i = 0; i + 1 < blocks_x; ++i) {
      const int left = j * blocks_x + i, right = left + 1;
      if (rng.Chance(options.join_blocks_probability) && !in_pair[left] && !in_pair[right]) {
        joined_right[left] = true;
        in_pair[left] = true;
        in_pair[right] = true;
      }
    }
  }
  for (int j = 0; j < count_y; ++j) {
    layout.corridors.emplace_back(grid_x0, corridor_y[j], grid_width, cells.corridor);
  }
  for (int i = 0; i < count_x; ++i) {
    for (int j = 0; j < blocks_y; ++j) {
      const bool left_out = i > 0 && i + 1 < count_x && joined_right[j * blocks_x + i - 1];
      if (left_out) continue;
      layout.corridors.emplace_back(corridor_x[i], corridor_y[j], cells.corridor,
                                    corridor_y[j + 1] + cells.corridor - corridor_y[j]);
    }
  }
  for (int y : corridor_y) {
    for (int x : corridor_x) {
      layout.crossings.emplace_back(x + cells.corridor / 2, y + cells.corridor / 2);
    }
  }

  for (int j = 0; j < blocks_y; ++j) {
    for (int i = 0; i < blocks_x;) {
      const int last = joined_right[j * blocks_x + i] ? i + 1 : i;
      const cv::Rect interior(corridor_x[i] + cells.corridor + wall,
                              corridor_y[j] + cells.corridor + wall,
                              corridor_x[last + 1] - wall - (corridor_x[i] + cells.corridor + wall),
                              block_heights[j] - 2 * wall);
      AddBlockRooms(interior, options, cells, rng, &layout.rooms);
      i = last + 1;
    }
  }

  // The outer rows: left and right span the full height (their end rooms
  // take the corners), bottom and top the corridor grid's width.
  const int mean_width = (cells.width_min + cells.width_max) / 2;
  const Interval grid_along_x{grid_x0, grid_width};
  const Interval grid_along_y{grid_y0, grid_height};
  const Interval full_along_y{y0 + wall, height - 2 * wall};
  const std::array<RowSpec, 4> strips = {
      RowSpec{false, {x0 + wall, strip_depth[0]}, {Side::kRight}, false, grid_along_y},
      RowSpec{false,
              {x0 + width - wall - strip_depth[1], strip_depth[1]},
              {Side::kLeft},
              false,
              grid_along_y},
      RowSpec{true, {y0 + wall, strip_depth[2]}, {Side::kTop}, false, grid_along_x},
      RowSpec{true,
              {y0 + height - wall - strip_depth[3], strip_depth[3]},
              {Side::kBottom},
              false,
              grid_along_x}};
  for (int side = 0; side < 4; ++side) {
    if (!strip_depth[side]) continue;
    const Interval along = side < 2 ? full_along_y : grid_along_x;
    AddRoomRow(SplitIntoSegments(along, mean_width, cells.width_min, wall, rng), strips[side],
               options, cells, rng, &layout.rooms);
  }
  return layout;
}

// ---------------------------------------------------------------------------
// Furniture

struct Piece {
  double length_min_m, length_max_m;  // along the wall (or the room's long axis)
  double depth_min_m, depth_max_m;
  bool against_wall;
};

const Piece kDesk{1.2, 1.8, 0.6, 0.8, true};
const Piece kCabinet{0.8, 1.6, 0.4, 0.5, true};
const Piece kShelf{0.8, 2.0, 0.3, 0.4, true};
const Piece kBench{1.8, 3.5, 0.7, 0.9, true};
const Piece kCounter{2.0, 4.0, 0.6, 0.7, true};
const Piece kDeskIsland{1.6, 3.2, 1.4, 1.6, false};
const Piece kTableIsland{1.2, 2.4, 0.9, 1.4, false};

struct WeightedPiece {
  const Piece* piece;
  double weight;
};

std::vector<WeightedPiece> FurnitureMenu(RoomKind kind) {
  switch (kind) {
    case RoomKind::kOffice: return {{&kDesk, 3}, {&kCabinet, 2}, {&kShelf, 1}};
    case RoomKind::kMeeting: return {{&kTableIsland, 2}, {&kCabinet, 1}, {&kShelf, 1}};
    case RoomKind::kOpenPlan: return {{&kDeskIsland, 3}, {&kDesk, 2}, {&kCabinet, 1}};
    case RoomKind::kLab: return {{&kBench, 3}, {&kTableIsland, 1}, {&kCabinet, 1}};
    case RoomKind::kHall: return {{&kTableIsland, 2}, {&kCounter, 1}, {&kCabinet, 1}};
  }
  return {};
}

double FillFactor(RoomKind kind) {
  switch (kind) {
    case RoomKind::kOffice: return 1.1;
    case RoomKind::kMeeting: return 1.0;
    case RoomKind::kOpenPlan: return 1.2;
    case RoomKind::kLab: return 1.2;
    case RoomKind::kHall: return 0.4;
  }
  return 1.0;
}

// Places furniture in one room, checking each piece keeps the room passable.
class RoomFurnisher {
 public:
  RoomFurnisher(const Room& room, const CellSizes& cells, const cv::Mat& disk)
      : room_(room), cells_(cells), disk_(disk) {
    // A local frame: the room, its door openings and a patch of corridor
    // beyond each door, so the passage check sees the way out.
    const int reach = cells.wall + cells.Cells(1.0);
    frame_ = {room.interior.x - reach, room.interior.y - reach, room.interior.width + 2 * reach,
              room.interior.height + 2 * reach};
    free_ = cv::Mat::zeros(frame_.size(), CV_8U);
    free_(Local(room.interior)).setTo(255);
    interior_mask_ = cv::Mat::zeros(frame_.size(), CV_8U);
    interior_mask_(Local(room.interior)).setTo(255);
    const int keep_depth = cells.Cells(kDoorKeepClearDepth_m);
    const int keep_side = cells.Cells(kDoorKeepClearSide_m);
    for (const Door& door : room.doors) {
      cv::Rect outside = door.opening, keep_clear = door.opening;
      const int patch = reach - cells.wall;
      switch (door.side) {
        case Side::kBottom:
          outside = {door.opening.x, door.opening.y - patch, door.opening.width, patch};
          keep_clear = {door.opening.x - keep_side, room.interior.y,
                        door.opening.width + 2 * keep_side, keep_depth};
          break;
        case Side::kTop:
          outside = {door.opening.x, door.opening.y + cells.wall, door.opening.width, patch};
          keep_clear = {door.opening.x - keep_side, door.opening.y - keep_depth,
                        door.opening.width + 2 * keep_side, keep_depth};
          break;
        case Side::kLeft:
          outside = {door.opening.x - patch, door.opening.y, patch, door.opening.height};
          keep_clear = {room.interior.x, door.opening.y - keep_side, keep_depth,
                        door.opening.height + 2 * keep_side};
          break;
        case Side::kRight:
          outside = {door.opening.x + cells.wall, door.opening.y, patch, door.opening.height};
          keep_clear = {door.opening.x - keep_depth, door.opening.y - keep_side, keep_depth,
                        door.opening.height + 2 * keep_side};
          break;
      }
      free_(Local(door.opening)).setTo(255);
      free_(Local(outside)).setTo(255);
      keep_clear_.push_back(keep_clear & room.interior);
    }
  }

  // Adds pieces until `fill` of the floor is covered or attempts run out;
  // returns the pieces in canvas cells.
  std::vector<cv::Rect> Furnish(double fill, Rng& rng) {
    const std::vector<WeightedPiece> menu = FurnitureMenu(room_.kind);
    double weight_sum = 0.0;
    for (const auto& item : menu) weight_sum += item.weight;
    const double target_cells = fill * room_.interior.area();
    double covered_cells = 0.0;
    for (int attempt = 0; attempt < kFurnitureAttemptsPerRoom && covered_cells < target_cells;
         ++attempt) {
      double pick = rng.Real(0.0, weight_sum);
      const Piece* piece = menu.back().piece;
      for (const auto& item : menu) {
        if (pick < item.weight) {
          piece = item.piece;
          break;
        }
        pick -= item.weight;
      }
      const std::optional<cv::Rect> rect =
          piece->against_wall ? WallCandidate(*piece, rng) : IslandCandidate(*piece, rng);
      if (!rect || !Accept(*rect)) continue;
      pieces_.push_back(*rect);
      covered_cells += rect->area();
    }
    return pieces_;
  }

 private:
  cv::Rect Local(const cv::Rect& canvas_rect) const { return canvas_rect - frame_.tl(); }

  bool Blocked(const cv::Rect& rect) const {
    return cv::countNonZero(free_(Local(rect))) < rect.area();
  }

  bool InKeepClear(const cv::Rect& rect) const {
    for (const cv::Rect& zone : keep_clear_) {
      if ((rect & zone).area() > 0) return true;
    }
    return false;
  }

  // A piece flush against a random wall; small gaps along the wall close up.
  std::optional<cv::Rect> WallCandidate(const Piece& piece, Rng& rng) const {
    const cv::Rect& in = room_.interior;
    const Side side = static_cast<Side>(rng.Int(0, 3));
    const bool along_x = RunsAlongX(side);
    const int wall_length = along_x ? in.width : in.height;
    const int room_depth = along_x ? in.height : in.width;
    const int length = cells_.Cells(rng.Real(piece.length_min_m, piece.length_max_m));
    const int depth = cells_.Cells(rng.Real(piece.depth_min_m, piece.depth_max_m));
    if (length > wall_length || depth * 3 > room_depth) return std::nullopt;
    const int wall_start = along_x ? in.x : in.y;
    const int across_start = side == Side::kBottom ? in.y
                             : side == Side::kTop  ? in.y + in.height - depth
                             : side == Side::kLeft ? in.x
                                                   : in.x + in.width - depth;
    const Interval across{across_start, depth};
    int position = wall_start + rng.Int(0, wall_length - length);

    // Free cells before and after the piece along the wall, within its band.
    const auto band_free = [&](int at) { return !Blocked(RowRect(along_x, {at, 1}, across)); };
    const int snap = cells_.Cells(kSnapGap_m);
    int gap_before = 0;
    while (position - gap_before - 1 >= wall_start && band_free(position - gap_before - 1)) {
      ++gap_before;
    }
    if (gap_before > 0 && gap_before < snap) position -= gap_before;
    int gap_after = 0;
    while (position + length + gap_after < wall_start + wall_length &&
           band_free(position + length + gap_after)) {
      ++gap_after;
    }
    if (gap_after > 0 && gap_after < snap) return std::nullopt;
    return RowRect(along_x, {position, length}, across);
  }

  // A piece in the open, with a clear ring around it.
  std::optional<cv::Rect> IslandCandidate(const Piece& piece, Rng& rng) const {
    const cv::Rect& in = room_.interior;
    const int clearance = cells_.Cells(kIslandClearance_m);
    const int length = cells_.Cells(rng.Real(piece.length_min_m, piece.length_max_m));
    const int depth = cells_.Cells(rng.Real(piece.depth_min_m, piece.depth_max_m));
    const bool long_x = in.width >= in.height;  // tables follow the room's long axis
    const int width = long_x ? length : depth;
    const int height = long_x ? depth : length;
    if (in.width < width + 2 * clearance || in.height < height + 2 * clearance) {
      return std::nullopt;
    }
    const cv::Rect rect(rng.Int(in.x + clearance, in.x + in.width - clearance - width),
                        rng.Int(in.y + clearance, in.y + in.height - clearance - height), width,
                        height);
    const cv::Rect ring(rect.x - clearance, rect.y - clearance, width + 2 * clearance,
                        height + 2 * clearance);
    if (Blocked(ring) || InKeepClear(ring)) return std::nullopt;
    return rect;
  }

  // Keeps the piece if it overlaps nothing, leaves the doors clear and the
  // room passable: one connected passage region sweeping most of the floor.
  bool Accept(const cv::Rect& rect) {
    if ((rect & room_.interior) != rect || Blocked(rect) || InKeepClear(rect)) return false;
    cv::Mat trial = free_.clone();
    trial(Local(rect)).setTo(0);
    cv::Mat passage;
    cv::erode(trial, passage, disk_, {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::Mat components;
    if (cv::connectedComponents(passage, components, 8, CV_32S) != 2) return false;
    cv::Mat swept;
    cv::dilate(passage, swept, disk_);
    const cv::Mat floor = trial & interior_mask_;
    const int floor_cells = cv::countNonZero(floor);
    const int swept_cells = cv::countNonZero(swept & floor);
    if (swept_cells < kMinRoomCoverage * floor_cells) return false;
    free_ = trial;
    return true;
  }

  const Room& room_;
  const CellSizes& cells_;
  const cv::Mat& disk_;
  cv::Rect frame_;
  cv::Mat free_;           // frame cells free for the robot (room, doors, corridor patches)
  cv::Mat interior_mask_;  // frame cells inside the room
  std::vector<cv::Rect> keep_clear_;
  std::vector<cv::Rect> pieces_;
};

cv::Mat PassageDisk(const CellSizes& cells) {
  const int radius = cells.Cells(kPassageRadius_m);
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * radius + 1, 2 * radius + 1});
}

// ---------------------------------------------------------------------------
// Rendering and analysis

cv::Mat CellsView(const OccupancyGrid& grid) {
  return cv::Mat(grid.height_cells(), grid.width_cells(), CV_8S,
                 const_cast<int8_t*>(grid.cells().data()));
}

OccupancyGrid LabelsToGrid(const cv::Mat& labels, const CellSizes& cells) {
  OccupancyGrid grid(labels.cols, labels.rows, cells.resolution_m,
                     {-cells.Meters(cells.margin), -cells.Meters(cells.margin)});
  cv::Mat table(1, 256, CV_8S, cv::Scalar(OccupancyGrid::kOccupied));
  table.at<int8_t>(kOutsideLabel) = OccupancyGrid::kUnknown;
  table.at<int8_t>(kFreeLabel) = OccupancyGrid::kFree;
  cv::Mat view = CellsView(grid);
  cv::LUT(labels, table, view);
  return grid;
}

// Distance from each free cell's centre to the nearest blocked cell, in cells.
cv::Mat FreeDistance(const cv::Mat& labels) {
  cv::Mat distance;
  cv::distanceTransform(labels == kFreeLabel, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return distance;
}

// The yaw (a multiple of 90 degrees) with the longest free view from `cell`.
double OpenYaw(const cv::Mat& labels, cv::Point cell) {
  const std::array<cv::Point, 4> steps = {cv::Point(1, 0), cv::Point(0, 1), cv::Point(-1, 0),
                                          cv::Point(0, -1)};
  int best_direction = 0, best_length = -1;
  for (int direction = 0; direction < 4; ++direction) {
    int length = 0;
    for (cv::Point p = cell + steps[direction];
         p.inside({0, 0, labels.cols, labels.rows}) && labels.at<uint8_t>(p) == kFreeLabel;
         p += steps[direction]) {
      ++length;
    }
    if (length > best_length) {
      best_length = length;
      best_direction = direction;
    }
  }
  return WrapAngle(best_direction * M_PI / 2.0);
}

// Draws, furnishes and checks one building of `width` x `height` cells.
std::optional<GeneratedWorld> BuildWorld(int width, int height, const WorldgenOptions& options,
                                         const CellSizes& cells, const cv::Mat& disk) {
  Rng layout_rng(options.seed);
  std::optional<Layout> layout = MakeLayout(width, height, options, cells, layout_rng);
  if (!layout || layout->crossings.empty()) return std::nullopt;

  cv::Mat labels(layout->canvas, CV_8U, cv::Scalar(kOutsideLabel));
  labels(layout->building).setTo(kWallLabel);
  for (const cv::Rect& corridor : layout->corridors) labels(corridor).setTo(kFreeLabel);
  for (const Room& room : layout->rooms) {
    labels(room.interior).setTo(kFreeLabel);
    for (const Door& door : room.doors) labels(door.opening).setTo(kFreeLabel);
  }

  // Furniture draws come from their own stream so they never shift the layout.
  Rng furniture_rng(options.seed ^ 0x9e3779b97f4a7c15ULL);
  for (const Room& room : layout->rooms) {
    RoomFurnisher furnisher(room, cells, disk);
    const double fill = options.furniture_fill * FillFactor(room.kind);
    for (const cv::Rect& piece : furnisher.Furnish(fill, furniture_rng)) {
      labels(piece).setTo(kFurnitureLabel);
    }
  }

  // Start at the corridor crossing nearest the building's centre.
  const cv::Point centre(layout->building.x + width / 2, layout->building.y + height / 2);
  cv::Point start_cell = layout->crossings.front();
  for (const cv::Point& crossing : layout->crossings) {
    const cv::Point d = crossing - centre, best = start_cell - centre;
    if (d.dot(d) < best.dot(best)) start_cell = crossing;
  }

  // Free space the robot cannot reach from the start is filled solid.
  cv::Mat reachable = (labels == kFreeLabel);
  cv::floodFill(reachable, start_cell, cv::Scalar(128), nullptr, cv::Scalar(), cv::Scalar(), 4);
  labels.setTo(kWallLabel, reachable == 255);

  GeneratedWorld world;
  world.grid = LabelsToGrid(labels, cells);
  world.start = {world.grid.CellCenter({start_cell.x, start_cell.y}).x_m,
                 world.grid.CellCenter({start_cell.x, start_cell.y}).y_m,
                 OpenYaw(labels, start_cell)};
  world.start_clearance_m = cells.Meters(1) * (FreeDistance(labels).at<float>(start_cell) - 0.5);
  world.free_area_m2 = cells.SquareMeters(cv::countNonZero(labels == kFreeLabel));
  world.building_width_m = cells.Meters(width);
  world.building_height_m = cells.Meters(height);
  world.room_count = static_cast<int>(layout->rooms.size());
  world.corridors_x = layout->corridors_x;
  world.corridors_y = layout->corridors_y;
  world.loop_count = CountLoops(world.grid, kLoopObstacleMinSize_m);
  return world;
}

void Require(bool condition, const std::string& option, double value, const std::string& rule) {
  if (!condition) {
    std::ostringstream message;
    message << "worldgen option " << option << " = " << value << ": " << rule;
    throw std::invalid_argument(message.str());
  }
}

void Validate(const WorldgenOptions& o) {
  Require(o.target_free_area_m2 > 0.0, "target_free_area_m2", o.target_free_area_m2,
          "must be positive");
  Require(o.free_area_tolerance > 0.0 && o.free_area_tolerance < 0.5, "free_area_tolerance",
          o.free_area_tolerance, "must be in (0, 0.5)");
  Require(o.resolution_m > 0.0, "resolution_m", o.resolution_m, "must be positive");
  Require(o.wall_thickness_m >= 0.15 - 1e-9, "wall_thickness_m", o.wall_thickness_m,
          "must be at least 0.15 m");
  Require(o.margin_m >= 0.0, "margin_m", o.margin_m, "must not be negative");
  Require(o.corridor_width_m >= 1.2, "corridor_width_m", o.corridor_width_m,
          "must be at least 1.2 m (start clearance 0.6 m)");
  Require(o.door_width_min_m >= 1.0, "door_width_min_m", o.door_width_min_m,
          "must be at least 1.0 m");
  Require(o.door_width_max_m >= o.door_width_min_m, "door_width_max_m", o.door_width_max_m,
          "must be at least door_width_min_m");
  Require(o.room_width_min_m >= o.door_width_max_m + 2 * kDoorInset_m, "room_width_min_m",
          o.room_width_min_m, "must leave room for a door");
  Require(o.room_width_max_m >= o.room_width_min_m, "room_width_max_m", o.room_width_max_m,
          "must be at least room_width_min_m");
  Require(o.room_depth_min_m >= 2.0, "room_depth_min_m", o.room_depth_min_m,
          "must be at least 2 m");
  Require(o.room_depth_max_m >= o.room_depth_min_m, "room_depth_max_m", o.room_depth_max_m,
          "must be at least room_depth_min_m");
  Require(o.block_length_m >= o.room_width_min_m, "block_length_m", o.block_length_m,
          "must be at least room_width_min_m");
  Require(o.aspect_ratio >= 0.2 && o.aspect_ratio <= 5.0, "aspect_ratio", o.aspect_ratio,
          "must be in [0.2, 5]");
  Require(o.corridors_x == 0 || o.corridors_x >= 2, "corridors_x", o.corridors_x,
          "must be 0 (automatic) or at least 2");
  Require(o.corridors_y == 0 || o.corridors_y >= 2, "corridors_y", o.corridors_y,
          "must be 0 (automatic) or at least 2");
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"outer_rooms_probability", o.outer_rooms_probability},
        {"open_plan_probability", o.open_plan_probability},
        {"through_room_probability", o.through_room_probability},
        {"side_door_probability", o.side_door_probability},
        {"hall_probability", o.hall_probability},
        {"join_blocks_probability", o.join_blocks_probability},
        {"furniture_fill", o.furniture_fill}}) {
    Require(value >= 0.0 && value <= 1.0, name, value, "must be in [0, 1]");
  }
}

std::string FormatNumber(double value) {
  std::ostringstream text;
  text.precision(10);
  text << value;
  return text.str();
}

}  // namespace

WorldStyle ParseWorldStyle(const std::string& text) {
  if (text == "campus") return WorldStyle::kCampus;
  if (text == "office") return WorldStyle::kOffice;
  if (text == "test") return WorldStyle::kTest;
  throw std::invalid_argument("unknown world style '" + text + "' (campus, office or test)");
}

std::string WorldStyleName(WorldStyle style) {
  switch (style) {
    case WorldStyle::kCampus: return "campus";
    case WorldStyle::kOffice: return "office";
    case WorldStyle::kTest: return "test";
  }
  return "office";
}

WorldgenOptions DefaultWorldgenOptions(WorldStyle style) {
  WorldgenOptions options;
  options.style = style;
  switch (style) {
    case WorldStyle::kCampus:
      options.target_free_area_m2 = 2072.0;
      options.corridor_width_m = 2.0;
      options.room_width_min_m = 3.0;
      options.room_width_max_m = 6.0;
      options.room_depth_min_m = 4.0;
      options.room_depth_max_m = 6.0;
      options.block_length_m = 16.0;
      options.aspect_ratio = 1.4;
      options.outer_rooms_probability = 0.8;
      options.open_plan_probability = 0.25;
      options.through_room_probability = 0.12;
      options.side_door_probability = 0.25;
      options.hall_probability = 0.2;
      options.join_blocks_probability = 0.3;
      options.furniture_fill = 0.15;
      break;
    case WorldStyle::kOffice:
      options.target_free_area_m2 = 741.0;
      options.corridor_width_m = 1.6;
      options.room_width_min_m = 3.0;
      options.room_width_max_m = 5.5;
      options.room_depth_min_m = 3.5;
      options.room_depth_max_m = 5.0;
      options.block_length_m = 15.0;
      options.aspect_ratio = 1.5;
      options.outer_rooms_probability = 0.5;
      options.open_plan_probability = 0.2;
      options.through_room_probability = 0.1;
      options.side_door_probability = 0.2;
      options.hall_probability = 0.0;
      options.join_blocks_probability = 0.25;
      options.furniture_fill = 0.18;
      break;
    case WorldStyle::kTest:
      options.target_free_area_m2 = 110.0;
      options.corridor_width_m = 1.4;
      options.room_width_min_m = 2.6;
      options.room_width_max_m = 3.8;
      options.room_depth_min_m = 3.5;
      options.room_depth_max_m = 4.5;
      options.block_length_m = 9.0;
      options.aspect_ratio = 1.3;
      options.corridors_x = 2;
      options.corridors_y = 2;
      options.outer_rooms_probability = 0.0;
      options.open_plan_probability = 0.0;
      options.through_room_probability = 0.0;
      options.side_door_probability = 0.0;
      options.hall_probability = 0.0;
      options.furniture_fill = 0.15;
      break;
  }
  return options;
}

GeneratedWorld GenerateWorld(const WorldgenOptions& options) {
  Validate(options);
  const CellSizes cells(options);
  const cv::Mat disk = PassageDisk(cells);
  const double target = options.target_free_area_m2;

  // Search the building width (height follows the aspect ratio): scale by
  // the square root of the area error, bisect once the target is bracketed.
  int width = static_cast<int>(std::lround(
      std::sqrt(target / kExpectedFreeFraction * options.aspect_ratio) / options.resolution_m));
  int below = 0;                                // widest building found too small
  int above = std::numeric_limits<int>::max();  // narrowest found too large
  std::set<int> tried;
  std::optional<GeneratedWorld> best;
  int attempts = 0;
  while (attempts < kMaxLayoutAttempts) {
    ++attempts;
    tried.insert(width);
    const int height = std::max(1, static_cast<int>(std::lround(width / options.aspect_ratio)));
    std::optional<GeneratedWorld> world = BuildWorld(width, height, options, cells, disk);
    const double area = world ? world->free_area_m2 : 0.0;
    if (world && (!best || std::abs(area - target) < std::abs(best->free_area_m2 - target))) {
      best = std::move(world);
    }
    if (std::abs(area - target) <= kSearchGoal * target) break;
    if (area < target) {
      below = std::max(below, width);
    } else {
      above = std::min(above, width);
    }
    int next = area > 0.0 ? static_cast<int>(std::lround(width * std::sqrt(target / area)))
                          : width + width / 2 + 1;
    const auto usable = [&](int candidate) {
      return candidate > below && candidate < above && !tried.count(candidate);
    };
    if (!usable(next)) {
      next = above == std::numeric_limits<int>::max() ? below + 1 + below / 8
                                                      : below + (above - below) / 2;
    }
    if (!usable(next)) break;  // the bracket has closed
    width = next;
  }
  if (!best || std::abs(best->free_area_m2 - target) > options.free_area_tolerance * target) {
    std::ostringstream message;
    message << "worldgen: no " << WorldStyleName(options.style) << " layout reaches "
            << FormatNumber(target) << " m2 of free area within "
            << FormatNumber(options.free_area_tolerance * 100)
            << " % (closest: " << (best ? FormatNumber(best->free_area_m2) + " m2" : "none fits")
            << ")";
    throw std::runtime_error(message.str());
  }
  if (best->start_clearance_m < kStartClearanceMin_m) {
    throw std::runtime_error("worldgen: start clearance " + FormatNumber(best->start_clearance_m) +
                             " m is below " + FormatNumber(kStartClearanceMin_m) + " m");
  }
  best->layout_attempts = attempts;
  return *best;
}

int CountLoops(const OccupancyGrid& grid, double min_obstacle_size_m) {
  const cv::Mat blocked = CellsView(grid) != OccupancyGrid::kFree;
  cv::Mat components, stats, centroids;
  const int count = cv::connectedComponentsWithStats(blocked, components, stats, centroids, 8);
  const int min_cells = static_cast<int>(std::ceil(min_obstacle_size_m / grid.resolution_m()));
  int loops = 0;
  for (int label = 1; label < count; ++label) {
    const int x = stats.at<int>(label, cv::CC_STAT_LEFT);
    const int y = stats.at<int>(label, cv::CC_STAT_TOP);
    const int w = stats.at<int>(label, cv::CC_STAT_WIDTH);
    const int h = stats.at<int>(label, cv::CC_STAT_HEIGHT);
    const bool touches_border = x == 0 || y == 0 || x + w == blocked.cols || y + h == blocked.rows;
    if (!touches_border && w >= min_cells && h >= min_cells) ++loops;
  }
  return loops;
}

std::string RegenerateCommand(const WorldgenOptions& options, const std::string& name,
                              const std::string& out_dir) {
  return "aslam-worldgen --out " + out_dir + " --style " + WorldStyleName(options.style) +
         " --free-area " + FormatNumber(options.target_free_area_m2) + " --seed " +
         std::to_string(options.seed) + " --name " + name;
}

void WriteWorld(const GeneratedWorld& world, const WorldgenOptions& options,
                const std::string& name, const std::string& out_dir,
                const std::string& regenerate_command) {
  const fs::path dir(out_dir);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error(out_dir + ": cannot create folder: " + error.message());
  SaveMap(world.grid, (dir / "map").string(), MapImageFormat::kPgm);

  YAML::Emitter yaml;
  yaml.SetDoublePrecision(10);
  yaml << YAML::Comment("aslam world: ground-truth map, start pose, how it was generated");
  yaml << YAML::BeginMap;
  yaml << YAML::Key << "name" << YAML::Value << name;
  yaml << YAML::Key << "map" << YAML::Value << "map.yaml";
  yaml << YAML::Key << "start" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "x_m"
       << YAML::Value << world.start.x_m << YAML::Key << "y_m" << YAML::Value << world.start.y_m
       << YAML::Key << "yaw_rad" << YAML::Value << world.start.yaw_rad << YAML::EndMap;
  yaml << YAML::Key << "start_clearance_m" << YAML::Value << world.start_clearance_m;
  yaml << YAML::Key << "free_area_m2" << YAML::Value << world.free_area_m2;
  yaml << YAML::Key << "building_size_m" << YAML::Value << YAML::Flow << YAML::BeginSeq
       << world.building_width_m << world.building_height_m << YAML::EndSeq;
  yaml << YAML::Key << "map_size_cells" << YAML::Value << YAML::Flow << YAML::BeginSeq
       << world.grid.width_cells() << world.grid.height_cells() << YAML::EndSeq;
  yaml << YAML::Key << "rooms" << YAML::Value << world.room_count;
  yaml << YAML::Key << "corridors" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
       << "vertical" << YAML::Value << world.corridors_x << YAML::Key << "horizontal" << YAML::Value
       << world.corridors_y << YAML::EndMap;
  yaml << YAML::Key << "loops" << YAML::Value << world.loop_count;
  yaml << YAML::Key << "generator" << YAML::Value << YAML::BeginMap;
  yaml << YAML::Key << "command" << YAML::Value << regenerate_command;
  yaml << YAML::Key << "style" << YAML::Value << WorldStyleName(options.style);
  yaml << YAML::Key << "seed" << YAML::Value << options.seed;
  yaml << YAML::Key << "target_free_area_m2" << YAML::Value << options.target_free_area_m2;
  yaml << YAML::Key << "free_area_tolerance" << YAML::Value << options.free_area_tolerance;
  yaml << YAML::Key << "layout_attempts" << YAML::Value << world.layout_attempts;
  const std::vector<std::pair<const char*, double>> lengths = {
      {"resolution_m", options.resolution_m},
      {"wall_thickness_m", options.wall_thickness_m},
      {"margin_m", options.margin_m},
      {"corridor_width_m", options.corridor_width_m},
      {"door_width_min_m", options.door_width_min_m},
      {"door_width_max_m", options.door_width_max_m},
      {"room_width_min_m", options.room_width_min_m},
      {"room_width_max_m", options.room_width_max_m},
      {"room_depth_min_m", options.room_depth_min_m},
      {"room_depth_max_m", options.room_depth_max_m},
      {"block_length_m", options.block_length_m},
      {"aspect_ratio", options.aspect_ratio}};
  for (const auto& [key, value] : lengths) yaml << YAML::Key << key << YAML::Value << value;
  yaml << YAML::Key << "corridors_x" << YAML::Value << options.corridors_x;
  yaml << YAML::Key << "corridors_y" << YAML::Value << options.corridors_y;
  const std::vector<std::pair<const char*, double>> variety = {
      {"outer_rooms_probability", options.outer_rooms_probability},
      {"open_plan_probability", options.open_plan_probability},
      {"through_room_probability", options.through_room_probability},
      {"side_door_probability", options.side_door_probability},
      {"hall_probability", options.hall_probability},
      {"join_blocks_probability", options.join_blocks_probability},
      {"furniture_fill", options.furniture_fill}};
  for (const auto& [key, value] : variety) yaml << YAML::Key << key << YAML::Value << value;
  yaml << YAML::EndMap << YAML::EndMap;

  const fs::path world_path = dir / "world.yaml";
  std::ofstream world_file(world_path);
  world_file << yaml.c_str() << "\n";
  world_file.close();
  if (!world_file) throw std::runtime_error(world_path.string() + ": cannot write");

  const fs::path readme_path = dir / "README.md";
  std::ofstream readme(readme_path);
  readme << "# " << name << "\n\n"
         << "Generated " << WorldStyleName(options.style)
         << "-style floor plan (ROS map_server format: `map.yaml` + `map.pgm`; start pose and "
            "generator parameters in `world.yaml`).\n\n"
         << "| | |\n|---|---|\n"
         << "| free area (all reachable from the start) | "
         << FormatNumber(std::round(world.free_area_m2 * 10.0) / 10.0) << " m² (target "
         << FormatNumber(options.target_free_area_m2) << " m²) |\n"
         << "| building | " << FormatNumber(world.building_width_m) << " m × "
         << FormatNumber(world.building_height_m) << " m |\n"
         << "| map | " << world.grid.width_cells() << " × " << world.grid.height_cells()
         << " cells at " << FormatNumber(world.grid.resolution_m()) << " m, origin ("
         << FormatNumber(world.grid.origin_m().x_m) << ", "
         << FormatNumber(world.grid.origin_m().y_m) << ") |\n"
         << "| rooms | " << world.room_count << " |\n"
         << "| corridors | " << world.corridors_x << " vertical × " << world.corridors_y
         << " horizontal, " << FormatNumber(options.corridor_width_m) << " m wide |\n"
         << "| loops (around obstacles ≥ " << FormatNumber(kLoopObstacleMinSize_m) << " m) | "
         << world.loop_count << " |\n"
         << "| start | x " << FormatNumber(world.start.x_m) << " m, y "
         << FormatNumber(world.start.y_m) << " m, yaw " << FormatNumber(world.start.yaw_rad)
         << " rad (clearance " << FormatNumber(world.start_clearance_m) << " m) |\n\n"
         << "Walls " << FormatNumber(options.wall_thickness_m) << " m, doors "
         << FormatNumber(options.door_width_min_m) << "–" << FormatNumber(options.door_width_max_m)
         << " m; free 0, walls and furniture 100, outside the building unknown.\n\n"
         << "Regenerate (from the repository root, with the built tool on the PATH):\n\n"
         << "    " << regenerate_command << "\n";
  readme.close();
  if (!readme) throw std::runtime_error(readme_path.string() + ": cannot write");
}

}  // namespace aslam
