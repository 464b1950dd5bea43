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
constexpr uint8_t kSpeckleLabel = 4;

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
  std::vector<cv::Rect> cut_outs;  // interior cells given to an alcove or a dead end
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
      if (options.hall_door_spacing_m > 0.0) {
        // Long hall sides get several doors, one in each equal part.
        const int parts = std::max(
            1, static_cast<int>(
                   std::lround(along.size / double(cells.Cells(options.hall_door_spacing_m)))));
        for (int part = 0; part < parts; ++part) {
          const Interval piece{along.start + part * along.size / parts, along.size / parts};
          if (auto door = PlaceDoor(interior, side, piece, 2 * cells.door_min, 2 * cells.door_max,
                                    cells, rng)) {
            hall.doors.push_back(*door);
          }
        }
        continue;
      }
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

// One piece of furniture as drawn: solid rectangles and round blobs (an
// ellipse filling its rectangle). `footprint_cells` is the floor it takes,
// the floor under a table on legs and its chairs included.
struct Item {
  std::vector<cv::Rect> solid;
  std::vector<cv::Rect> round;
  double footprint_cells = 0.0;
};

// Pieces of the cluttered styles.
const Piece kClutterDesk{1.2, 1.6, 0.6, 0.8, true};
const Piece kClutterCabinet{0.5, 1.2, 0.4, 0.6, true};
const Piece kLabBench{1.8, 3.0, 0.7, 0.9, true};
const Piece kWallShelf{0.9, 2.4, 0.35, 0.5, true};
constexpr double kClutterIslandClearance_m = 0.8;  // free ring around a table or desk cluster
constexpr double kShelvingPerimeterAisle_m = 1.4;  // free band between shelving and hall walls

enum class ClutterKind { kDesk, kDeskCluster, kTable, kCabinet, kBench, kShelf };

struct WeightedClutter {
  ClutterKind kind;
  double weight;
};

std::vector<WeightedClutter> ClutterMenu(RoomKind kind) {
  using K = ClutterKind;
  switch (kind) {
    case RoomKind::kOffice:
      return {{K::kDesk, 4}, {K::kCabinet, 2}, {K::kShelf, 1}, {K::kTable, 1}};
    case RoomKind::kMeeting: return {{K::kTable, 4}, {K::kCabinet, 1}, {K::kShelf, 1}};
    case RoomKind::kOpenPlan:
      return {{K::kDeskCluster, 4}, {K::kDesk, 2}, {K::kCabinet, 1}, {K::kTable, 1}};
    case RoomKind::kLab: return {{K::kBench, 3}, {K::kTable, 2}, {K::kCabinet, 1}, {K::kShelf, 1}};
    case RoomKind::kHall:
      return {{K::kDeskCluster, 3}, {K::kTable, 2}, {K::kCabinet, 1}, {K::kShelf, 1}};
  }
  return {};
}

// Cluttered rooms: open-plan halls are furnished like offices, not as halls.
double ClutterFillFactor(RoomKind kind) {
  switch (kind) {
    case RoomKind::kOffice: return 1.0;
    case RoomKind::kMeeting: return 0.8;
    case RoomKind::kOpenPlan: return 1.1;
    case RoomKind::kLab: return 1.1;
    case RoomKind::kHall: return 0.9;
  }
  return 1.0;
}

// A count with mean `mean`: its whole part, plus one by chance for the rest.
int DrawCount(double mean, Rng& rng) {
  const double whole = std::floor(mean);
  return static_cast<int>(whole) + (rng.Chance(mean - whole) ? 1 : 0);
}

// Places furniture in one room, checking each piece keeps the room passable.
class RoomFurnisher {
 public:
  // `labels`, when given (the textured styles), also keeps out of the room
  // the cells already drawn solid (cut corners, ragged walls) and its cut-outs.
  RoomFurnisher(const Room& room, const CellSizes& cells, const cv::Mat& disk, double coverage_min,
                const cv::Mat* labels = nullptr)
      : room_(room), cells_(cells), disk_(disk), coverage_min_(coverage_min) {
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
    if (labels) {
      cv::Mat drawn_free = cv::Mat::zeros(frame_.size(), CV_8U);
      const cv::Rect inside = frame_ & cv::Rect(0, 0, labels->cols, labels->rows);
      drawn_free(Local(inside)).setTo(255, (*labels)(inside) == kFreeLabel);
      for (const cv::Rect& cut : room.cut_outs) drawn_free(Local(cut & frame_)).setTo(0);
      free_ &= drawn_free;
      interior_mask_ &= free_;
    }
    furniture_ = cv::Mat::zeros(frame_.size(), CV_8U);
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
      if (!rect || !Accept(Item{{*rect}, {}, double(rect->area())})) continue;
      pieces_.push_back(*rect);
      covered_cells += rect->area();
    }
    return pieces_;
  }

  // The cluttered styles: desks with chairs, desk clusters, tables (on legs
  // or solid) with chairs, cabinets, shelves, lab benches, plants; a
  // shelving hall first gets its rows of shelving.
  void FurnishCluttered(const WorldgenOptions& options, bool shelving, Rng& rng) {
    floor_cells_ = cv::countNonZero(interior_mask_);
    if (shelving) AddShelvingRows(rng);
    const std::vector<WeightedClutter> menu = ClutterMenu(room_.kind);
    double weight_sum = 0.0;
    for (const auto& entry : menu) weight_sum += entry.weight;
    const double target_cells = options.clutter_fill * ClutterFillFactor(room_.kind) * floor_cells_;
    // Bigger rooms get more tries: they hold more pieces.
    const int attempts =
        kFurnitureAttemptsPerRoom + static_cast<int>(cells_.SquareMeters(floor_cells_));
    for (int attempt = 0; attempt < attempts && footprint_cells_ < target_cells; ++attempt) {
      double pick = rng.Real(0.0, weight_sum);
      ClutterKind kind = menu.back().kind;
      for (const auto& entry : menu) {
        if (pick < entry.weight) {
          kind = entry.kind;
          break;
        }
        pick -= entry.weight;
      }
      std::optional<Item> item;
      switch (kind) {
        case ClutterKind::kDesk: item = DeskWithChairs(options, rng); break;
        case ClutterKind::kDeskCluster: item = DeskCluster(options, rng); break;
        case ClutterKind::kTable: item = TableWithChairs(options, rng); break;
        case ClutterKind::kCabinet: item = WallItem(kClutterCabinet, rng); break;
        case ClutterKind::kBench: item = WallItem(kLabBench, rng); break;
        case ClutterKind::kShelf: item = WallItem(kWallShelf, rng); break;
      }
      if (item) Accept(*item);
    }
    const int plants =
        DrawCount(options.plants_per_100m2 * cells_.SquareMeters(floor_cells_) / 100.0, rng);
    for (int plant = 0; plant < plants; ++plant) {
      for (int attempt = 0; attempt < 5; ++attempt) {
        if (Accept(Plant(rng))) break;
      }
    }
  }

  // Writes the furniture placed by FurnishCluttered into `labels`.
  void DrawFurniture(cv::Mat& labels) const {
    const cv::Rect inside = frame_ & cv::Rect(0, 0, labels.cols, labels.rows);
    labels(inside).setTo(kFurnitureLabel, furniture_(Local(inside)));
  }
  double floor_cells() const { return floor_cells_; }
  double footprint_cells() const { return footprint_cells_; }

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

  bool Inside(const cv::Rect& rect) const {
    return (rect & room_.interior) == rect && rect.area() > 0;
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
    const int length = cells_.Cells(rng.Real(piece.length_min_m, piece.length_max_m));
    const int depth = cells_.Cells(rng.Real(piece.depth_min_m, piece.depth_max_m));
    return IslandRect(length, depth, cells_.Cells(kIslandClearance_m), rng);
  }

  // A `length` x `depth` rectangle along the room's long axis, with a free
  // ring of `clearance` around it clear of the doors.
  std::optional<cv::Rect> IslandRect(int length, int depth, int clearance, Rng& rng) const {
    const cv::Rect& in = room_.interior;
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

  std::optional<Item> WallItem(const Piece& piece, Rng& rng) const {
    const std::optional<cv::Rect> rect = WallCandidate(piece, rng);
    if (!rect) return std::nullopt;
    return Item{{*rect}, {}, double(rect->area())};
  }

  // A chair of `size` cells at `corner`: a round blob (an office chair's
  // seat and base) or, by chance, its four legs.
  void AddChair(cv::Point corner, int size, const WorldgenOptions& options, Rng& rng,
                Item* item) const {
    const cv::Rect seat(corner.x, corner.y, size, size);
    if (!Inside(seat) || Blocked(seat) || InKeepClear(seat)) return;
    for (const cv::Rect& other : item->round) {
      if ((other & seat).area() > 0) return;
    }
    for (const cv::Rect& other : item->solid) {
      if ((other & seat).area() > 0) return;
    }
    if (rng.Chance(options.chair_legs_probability)) {
      for (const cv::Point leg :
           {seat.tl(), cv::Point(seat.x + size - 1, seat.y), cv::Point(seat.x, seat.y + size - 1),
            seat.br() - cv::Point(1, 1)}) {
        item->solid.emplace_back(leg.x, leg.y, 1, 1);
      }
    } else {
      item->round.push_back(seat);
    }
    item->footprint_cells += seat.area();
  }

  int ChairSize(Rng& rng) const { return cells_.Cells(rng.Real(0.4, 0.55)); }

  // Chairs along the `side` face of `top` (outside it, or tucked under it
  // by up to `tuck` cells), about one per `spacing` cells.
  void AddChairsAlong(const cv::Rect& top, Side side, int spacing, int tuck,
                      const WorldgenOptions& options, Rng& rng, Item* item) const {
    const bool along_x = RunsAlongX(side);
    const Interval along = AlongInterval(top, along_x);
    const int seats = std::max(1, along.size / spacing);
    for (int seat = 0; seat < seats; ++seat) {
      const int chairs = DrawCount(options.chairs_per_desk, rng);
      if (chairs == 0) continue;
      const int size = ChairSize(rng);
      const int centre = along.start + (2 * seat + 1) * along.size / (2 * seats) +
                         rng.Int(-cells_.Cells(0.1), cells_.Cells(0.1));
      const int gap = rng.Int(-tuck, cells_.Cells(0.25));
      int across = 0;
      switch (side) {
        case Side::kBottom: across = top.y - gap - size; break;
        case Side::kTop: across = top.y + top.height + gap; break;
        case Side::kLeft: across = top.x - gap - size; break;
        case Side::kRight: across = top.x + top.width + gap; break;
      }
      const cv::Point corner =
          along_x ? cv::Point(centre - size / 2, across) : cv::Point(across, centre - size / 2);
      AddChair(corner, size, options, rng, item);
    }
  }

  // The room wall a wall piece stands against (its free side faces away).
  Side WallOf(const cv::Rect& rect) const {
    const cv::Rect& in = room_.interior;
    const bool bottom = rect.y == in.y, top = rect.y + rect.height == in.y + in.height;
    const bool left = rect.x == in.x, right = rect.x + rect.width == in.x + in.width;
    // A piece in a corner touches two walls; its long side is against the wall.
    if ((bottom || top) && (rect.width >= rect.height || !(left || right))) {
      return bottom ? Side::kBottom : Side::kTop;
    }
    return left ? Side::kLeft : Side::kRight;
  }

  static Side Opposite(Side side) {
    switch (side) {
      case Side::kBottom: return Side::kTop;
      case Side::kTop: return Side::kBottom;
      case Side::kLeft: return Side::kRight;
      case Side::kRight: return Side::kLeft;
    }
    return side;
  }

  std::optional<Item> DeskWithChairs(const WorldgenOptions& options, Rng& rng) const {
    const std::optional<cv::Rect> desk = WallCandidate(kClutterDesk, rng);
    if (!desk) return std::nullopt;
    Item item{{*desk}, {}, double(desk->area())};
    AddChairsAlong(*desk, Opposite(WallOf(*desk)), desk->area(), 0, options, rng, &item);
    return item;
  }

  // Two rows of desks back to back in the open, chairs on both long sides.
  std::optional<Item> DeskCluster(const WorldgenOptions& options, Rng& rng) const {
    const int desks = rng.Int(2, 4);
    const int desk_width = cells_.Cells(rng.Real(1.2, 1.6));
    const int depth = 2 * cells_.Cells(rng.Real(0.7, 0.8));
    const std::optional<cv::Rect> top =
        IslandRect(desks * desk_width, depth, cells_.Cells(kClutterIslandClearance_m), rng);
    if (!top) return std::nullopt;
    Item item{{*top}, {}, double(top->area())};
    const bool long_x = top->width >= top->height;
    for (Side side : long_x ? std::array<Side, 2>{Side::kBottom, Side::kTop}
                            : std::array<Side, 2>{Side::kLeft, Side::kRight}) {
      AddChairsAlong(*top, side, desk_width, 0, options, rng, &item);
    }
    return item;
  }

  // A table: four legs (by chance) or a solid top, chairs around it.
  std::optional<Item> TableWithChairs(const WorldgenOptions& options, Rng& rng) const {
    const int length = cells_.Cells(rng.Real(1.2, 2.4));
    const int depth = cells_.Cells(rng.Real(0.8, 1.2));
    const std::optional<cv::Rect> top =
        IslandRect(length, depth, cells_.Cells(kClutterIslandClearance_m), rng);
    if (!top) return std::nullopt;
    Item item;
    item.footprint_cells = top->area();
    const bool legs = rng.Chance(options.table_legs_probability);
    if (legs) {
      const int leg = cells_.Cells(rng.Real(0.05, 0.08));
      const int inset = 1;
      const int x0 = top->x + inset, x1 = top->x + top->width - inset - leg;
      const int y0 = top->y + inset, y1 = top->y + top->height - inset - leg;
      for (const cv::Point corner :
           {cv::Point(x0, y0), cv::Point(x1, y0), cv::Point(x0, y1), cv::Point(x1, y1)}) {
        item.solid.emplace_back(corner.x, corner.y, leg, leg);
      }
    } else {
      item.solid.push_back(*top);
    }
    // Chairs tuck under a table on legs.
    const int tuck = legs ? cells_.Cells(0.2) : 0;
    const bool long_x = top->width >= top->height;
    const int seat_spacing = cells_.Cells(0.7);
    for (Side side : long_x ? std::array<Side, 2>{Side::kBottom, Side::kTop}
                            : std::array<Side, 2>{Side::kLeft, Side::kRight}) {
      AddChairsAlong(*top, side, seat_spacing, tuck, options, rng, &item);
    }
    return item;
  }

  // A round pot against a wall, often in a corner.
  Item Plant(Rng& rng) const {
    const cv::Rect& in = room_.interior;
    const int size = cells_.Cells(rng.Real(0.3, 0.6));
    const int offset = rng.Int(0, cells_.Cells(0.1));
    const bool corner = rng.Chance(0.5);
    const Side side = static_cast<Side>(rng.Int(0, 3));
    const bool along_x = RunsAlongX(side);
    const Interval along = AlongInterval(in, along_x);
    const int slack = std::max(0, along.size - size - 2 * offset);
    const int position =
        along.start + offset + (corner ? (rng.Chance(0.5) ? 0 : slack) : rng.Int(0, slack));
    int across = 0;
    switch (side) {
      case Side::kBottom: across = in.y + offset; break;
      case Side::kTop: across = in.y + in.height - offset - size; break;
      case Side::kLeft: across = in.x + offset; break;
      case Side::kRight: across = in.x + in.width - offset - size; break;
    }
    const cv::Rect pot = RowRect(along_x, {position, size}, {across, size});
    return Item{{}, {pot}, double(pot.area())};
  }

  // Parallel rows of shelving along the hall's long axis, aisles between
  // them and cross aisles cutting the rows into sections.
  void AddShelvingRows(Rng& rng) {
    const cv::Rect& in = room_.interior;
    const bool long_x = in.width >= in.height;
    const int perimeter = cells_.Cells(kShelvingPerimeterAisle_m);
    const Interval along = AlongInterval(in, long_x);
    const Interval across = AlongInterval(in, !long_x);
    const int row_depth = cells_.Cells(rng.Real(0.9, 1.2));
    const int aisle = cells_.Cells(rng.Real(1.6, 2.4));
    for (int row = across.start + perimeter; row + row_depth <= across.end() - perimeter;
         row += row_depth + aisle) {
      for (int start = along.start + perimeter; start < along.end() - perimeter;) {
        const int length =
            std::min(cells_.Cells(rng.Real(8.0, 16.0)), along.end() - perimeter - start);
        if (length >= cells_.Cells(1.5)) {
          const cv::Rect section = RowRect(long_x, {start, length}, {row, row_depth});
          Accept(Item{{section}, {}, double(section.area())});
        }
        start += length + cells_.Cells(rng.Real(2.0, 3.0));
      }
    }
  }

  void Draw(const Item& item, cv::Mat& mask, uint8_t value) const {
    for (const cv::Rect& part : item.solid) mask(Local(part)).setTo(value);
    for (const cv::Rect& part : item.round) {
      const cv::Mat blob = cv::getStructuringElement(cv::MORPH_ELLIPSE, part.size());
      mask(Local(part)).setTo(value, blob);
    }
  }

  // Keeps the piece if it overlaps nothing, leaves the doors clear and the
  // room passable: one connected passage region sweeping most of the floor.
  bool Accept(const Item& item) {
    for (const auto* parts : {&item.solid, &item.round}) {
      for (const cv::Rect& rect : *parts) {
        if ((rect & room_.interior) != rect || Blocked(rect) || InKeepClear(rect)) return false;
      }
    }
    cv::Mat trial = free_.clone();
    Draw(item, trial, 0);
    cv::Mat passage;
    cv::erode(trial, passage, disk_, {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::Mat components;
    if (cv::connectedComponents(passage, components, 8, CV_32S) != 2) return false;
    cv::Mat swept;
    cv::dilate(passage, swept, disk_);
    const cv::Mat floor = trial & interior_mask_;
    const int floor_cells = cv::countNonZero(floor);
    const int swept_cells = cv::countNonZero(swept & floor);
    if (swept_cells < coverage_min_ * floor_cells) return false;
    free_ = trial;
    Draw(item, furniture_, 255);
    footprint_cells_ += item.footprint_cells;
    return true;
  }

  const Room& room_;
  const CellSizes& cells_;
  const cv::Mat& disk_;
  double coverage_min_;
  cv::Rect frame_;
  cv::Mat free_;           // frame cells free for the robot (room, doors, corridor patches)
  cv::Mat interior_mask_;  // frame cells inside the room
  cv::Mat furniture_;      // frame cells under furniture
  std::vector<cv::Rect> keep_clear_;
  std::vector<cv::Rect> pieces_;
  double floor_cells_ = 0.0;
  double footprint_cells_ = 0.0;
};

cv::Mat DiskElement(int radius) {
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * radius + 1, 2 * radius + 1});
}

// ---------------------------------------------------------------------------
// Texture of the cluttered styles: niches, cut corners, ragged walls, speckle

// Any option that changes the drawn walls or adds texture.
bool Textured(const WorldgenOptions& o) {
  return o.alcove_probability > 0.0 || o.dead_end_probability > 0.0 ||
         o.corner_cut_probability > 0.0 || o.ragged_edge_probability > 0.0 ||
         o.speckle_per_m2 > 0.0 || o.clutter_fill > 0.0;
}

bool AllLabelled(const cv::Mat& labels, const cv::Rect& rect, uint8_t label) {
  const cv::Rect inside = rect & cv::Rect(0, 0, labels.cols, labels.rows);
  return inside == rect && cv::countNonZero(labels(rect) != label) == 0;
}

// Alcoves (a shallow niche) and dead ends (a corridor stub) taken from a
// room's corner along a wall with a door, opening onto the corridor behind.
void CarveNiches(const WorldgenOptions& options, const CellSizes& cells, Rng& rng, Layout* layout,
                 cv::Mat& labels) {
  const int wall = cells.wall;
  for (Room& room : layout->rooms) {
    if (room.kind == RoomKind::kHall || room.doors.empty()) continue;
    const bool dead_end = rng.Chance(options.dead_end_probability);
    const bool alcove = !dead_end && rng.Chance(options.alcove_probability);
    if (!dead_end && !alcove) continue;
    const Side side = room.doors[rng.Int(0, static_cast<int>(room.doors.size()) - 1)].side;
    const bool along_x = RunsAlongX(side);
    const Interval along = AlongInterval(room.interior, along_x);
    const Interval across = AlongInterval(room.interior, !along_x);
    const int width = cells.Cells(dead_end ? rng.Real(1.0, 1.4) : rng.Real(1.0, 2.2));
    int depth = cells.Cells(dead_end ? rng.Real(2.0, 4.0) : rng.Real(0.6, 1.4));
    const bool at_start = rng.Chance(0.5);  // the corner at the wall's start or end
    depth = std::min(depth, across.size - wall - cells.Cells(1.5));
    if (depth < cells.Cells(dead_end ? 2.0 : 0.6) || width + wall > along.size - cells.Cells(1.5)) {
      continue;
    }
    const int position = at_start ? along.start : along.end() - width;
    const bool inward_up = side == Side::kBottom || side == Side::kLeft;
    const int face = inward_up ? across.start : across.end();  // the wall's inner face
    const Interval niche_across = inward_up ? Interval{face, depth} : Interval{face - depth, depth};
    const Interval back_across =
        inward_up ? Interval{face + depth, wall} : Interval{face - depth - wall, wall};
    const Interval mouth_across = inward_up ? Interval{face - wall, wall} : Interval{face, wall};
    const Interval behind_across =
        inward_up ? Interval{face - wall - 1, 1} : Interval{face + wall, 1};
    const Interval side_wall_along =
        at_start ? Interval{position + width, wall} : Interval{position - wall, wall};
    const Interval with_wall_along{at_start ? position : position - wall, width + wall};
    const Interval whole_across{std::min(niche_across.start, back_across.start), depth + wall};
    const cv::Rect cut = RowRect(along_x, with_wall_along, whole_across);
    // Only onto free floor behind the wall, and well away from every door.
    if (!AllLabelled(labels, RowRect(along_x, {position, width}, behind_across), kFreeLabel)) {
      continue;
    }
    const int keep = cells.Cells(kDoorKeepClearDepth_m);
    const cv::Rect keep_zone(cut.x - keep, cut.y - keep, cut.width + 2 * keep,
                             cut.height + 2 * keep);
    bool near_door = false;
    for (const Door& door : room.doors) near_door |= (door.opening & keep_zone).area() > 0;
    if (near_door || !AllLabelled(labels, cut, kFreeLabel)) continue;

    labels(RowRect(along_x, {position, width}, niche_across)).setTo(kFreeLabel);
    labels(RowRect(along_x, {position, width}, mouth_across)).setTo(kFreeLabel);
    labels(RowRect(along_x, with_wall_along, back_across)).setTo(kWallLabel);
    labels(RowRect(along_x, side_wall_along, whole_across)).setTo(kWallLabel);
    room.cut_outs.push_back(cut);
  }
}

// Room corners cut off by a diagonal wall; the two legs differ, so the cut
// is at an angle other than 45 degrees as often as not.
void CutCorners(const WorldgenOptions& options, const CellSizes& cells, Rng& rng,
                const Layout& layout, cv::Mat& labels) {
  for (const Room& room : layout.rooms) {
    const cv::Rect& in = room.interior;
    for (int corner = 0; corner < 4; ++corner) {
      if (!rng.Chance(options.corner_cut_probability)) continue;
      const int leg_x = cells.Cells(rng.Real(0.8, 2.2));
      const int leg_y = cells.Cells(rng.Real(0.8, 2.2));
      if (3 * leg_x > in.width || 3 * leg_y > in.height) continue;
      const bool right = corner & 1, top = corner & 2;
      const cv::Point apex(right ? in.x + in.width - 1 : in.x, top ? in.y + in.height - 1 : in.y);
      const cv::Point along_x(apex.x + (right ? -leg_x : leg_x), apex.y);
      const cv::Point along_y(apex.x, apex.y + (top ? -leg_y : leg_y));
      const cv::Rect box = cv::boundingRect(std::vector<cv::Point>{apex, along_x, along_y});
      const int keep = cells.Cells(kDoorKeepClearDepth_m);
      const cv::Rect keep_zone(box.x - keep, box.y - keep, box.width + 2 * keep,
                               box.height + 2 * keep);
      bool clear = AllLabelled(labels, box, kFreeLabel);
      for (const Door& door : room.doors) clear &= (door.opening & keep_zone).area() == 0;
      for (const cv::Rect& cut : room.cut_outs) clear &= (cut & keep_zone).area() == 0;
      if (!clear) continue;
      const std::vector<cv::Point> triangle{apex, along_x, along_y};
      cv::fillConvexPoly(labels, triangle, cv::Scalar(kWallLabel), cv::LINE_8);
    }
  }
}

// Per-cell noise smoothed over a few cells, and its `share` quantile: cells
// below it come in runs along a wall, as in a lidar-made map.
cv::Mat SmoothNoise(cv::Size size, Rng& rng) {
  cv::Mat noise(size, CV_32F);
  for (int row = 0; row < size.height; ++row) {
    float* line = noise.ptr<float>(row);
    for (int col = 0; col < size.width; ++col) line[col] = static_cast<float>(rng.Unit());
  }
  cv::GaussianBlur(noise, noise, {0, 0}, 1.5);
  return noise;
}

float Quantile(const cv::Mat& noise, double share) {
  std::vector<float> values(noise.begin<float>(), noise.end<float>());
  const std::size_t index =
      std::min(values.size() - 1, static_cast<std::size_t>(std::max(0.0, share) * values.size()));
  std::nth_element(values.begin(), values.begin() + index, values.end());
  return values[index];
}

// Wall faces pushed into the room by one or two cells and the building's
// outer face by one cell either way; never inside `keep`.
void RaggedEdges(const WorldgenOptions& options, Rng& rng, const cv::Mat& keep, cv::Mat& labels) {
  const cv::Mat noise = SmoothNoise(labels.size(), rng);
  const double share = options.ragged_edge_probability;
  const float one_cell = Quantile(noise, share), two_cells = Quantile(noise, share / 3.0);
  const float indent = Quantile(noise, 1.0 - share / 2.0);
  const cv::Mat cross = cv::getStructuringElement(cv::MORPH_CROSS, {3, 3});
  const cv::Mat wall = labels == kWallLabel, free = labels == kFreeLabel;
  cv::Mat near_wall, first, near_first;
  cv::dilate(wall, near_wall, cross);
  first = free & near_wall & (noise < one_cell) & ~keep;
  cv::dilate(first, near_first, cross);
  const cv::Mat second = free & ~first & near_first & (noise < two_cells) & ~keep;
  const cv::Mat outside = labels == kOutsideLabel;
  cv::Mat near_outside;
  cv::dilate(outside, near_outside, cross);
  const cv::Mat bulge = outside & near_wall & (noise < one_cell);
  const cv::Mat dent = wall & near_outside & (noise > indent);
  labels.setTo(kWallLabel, first | second | bulge);
  labels.setTo(kOutsideLabel, dent);
}

// Isolated occupied cells (some in pairs) one or two cells off walls and
// furniture, never inside `keep`.
void Speckle(const WorldgenOptions& options, const CellSizes& cells, Rng& rng,
             const cv::Rect& building, const cv::Mat& keep, cv::Mat& labels) {
  cv::Mat distance;
  cv::distanceTransform(labels == kFreeLabel, distance, cv::DIST_C, 3);
  const auto candidate = [&](cv::Point cell) {
    const float d = distance.at<float>(cell);
    return d >= 2.0f && d <= 3.0f && !keep.at<uint8_t>(cell) &&
           labels.at<uint8_t>(cell) == kFreeLabel;
  };
  const double floor_m2 = cells.SquareMeters(cv::countNonZero(labels == kFreeLabel));
  const int count = static_cast<int>(std::lround(options.speckle_per_m2 * floor_m2));
  int placed = 0;
  for (int attempt = 0; attempt < 200 * count && placed < count; ++attempt) {
    const cv::Point cell(rng.Int(building.x, building.x + building.width - 1),
                         rng.Int(building.y, building.y + building.height - 1));
    if (!candidate(cell)) continue;
    const cv::Point pair = cell + cv::Point(rng.Int(0, 1), 0) + cv::Point(0, rng.Int(0, 1));
    labels.at<uint8_t>(cell) = kSpeckleLabel;
    if (rng.Chance(0.3) && candidate(pair)) labels.at<uint8_t>(pair) = kSpeckleLabel;
    ++placed;
  }
}

// Free space a disk `radius` cells wide cannot reach from `start` (behind a
// gap narrower than the robot) is filled solid; the floor under tables
// and between chair legs, which no disk centre sweeps, stays free.
void FillRobotPockets(int radius, cv::Point start, cv::Mat& labels) {
  const cv::Mat disk = DiskElement(radius);
  cv::Mat centres;
  cv::erode(labels == kFreeLabel, centres, disk, {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  if (!centres.at<uint8_t>(start)) return;
  cv::Mat reached = centres.clone();
  cv::floodFill(reached, start, cv::Scalar(128), nullptr, cv::Scalar(), cv::Scalar(), 8);
  cv::Mat swept_from_start, swept_elsewhere;
  cv::dilate(reached == 128, swept_from_start, disk);
  cv::dilate(reached == 255, swept_elsewhere, disk);
  labels.setTo(kWallLabel, (labels == kFreeLabel) & swept_elsewhere & ~swept_from_start);
}

cv::Mat PassageDisk(const WorldgenOptions& options, const CellSizes& cells) {
  return DiskElement(cells.Cells(options.passage_width_m / 2.0));
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

  // Start at the corridor crossing nearest the building's centre.
  const cv::Point centre(layout->building.x + width / 2, layout->building.y + height / 2);
  cv::Point start_cell = layout->crossings.front();
  for (const cv::Point& crossing : layout->crossings) {
    const cv::Point d = crossing - centre, best = start_cell - centre;
    if (d.dot(d) < best.dot(best)) start_cell = crossing;
  }

  // Texture draws come from a third stream, used only by the textured styles.
  const bool textured = Textured(options);
  Rng texture_rng(options.seed ^ 0xd1b54a32d192ed03ULL);
  cv::Mat near_doors, around_doors;  // door openings grown by one cell and by a metre
  if (textured) {
    cv::Mat openings = cv::Mat::zeros(labels.size(), CV_8U);
    for (const Room& room : layout->rooms) {
      for (const Door& door : room.doors) openings(door.opening).setTo(255);
    }
    cv::dilate(openings, near_doors, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
    cv::dilate(openings, around_doors, DiskElement(cells.Cells(1.0)));
    const cv::Mat start_zone = cv::Mat::zeros(labels.size(), CV_8U);
    cv::circle(start_zone, start_cell, cells.Cells(1.0), cv::Scalar(255), cv::FILLED);
    near_doors |= start_zone;
    around_doors |= start_zone;
    CarveNiches(options, cells, texture_rng, &*layout, labels);
    CutCorners(options, cells, texture_rng, *layout, labels);
  }

  // Furniture draws come from their own stream so they never shift the layout.
  Rng furniture_rng(options.seed ^ 0x9e3779b97f4a7c15ULL);
  double floor_cells = 0.0, footprint_cells = 0.0;
  for (const Room& room : layout->rooms) {
    RoomFurnisher furnisher(room, cells, disk, options.room_coverage_min,
                            textured ? &labels : nullptr);
    if (options.clutter_fill > 0.0) {
      const bool shelving =
          room.kind == RoomKind::kHall && furniture_rng.Chance(options.shelving_hall_probability);
      furnisher.FurnishCluttered(options, shelving, furniture_rng);
      furnisher.DrawFurniture(labels);
      floor_cells += furnisher.floor_cells();
      footprint_cells += furnisher.footprint_cells();
      continue;
    }
    const double fill = options.furniture_fill * FillFactor(room.kind);
    for (const cv::Rect& piece : furnisher.Furnish(fill, furniture_rng)) {
      labels(piece).setTo(kFurnitureLabel);
    }
  }

  // Ragged walls come after the furniture, which stands flush against the straight wall.
  if (textured && options.ragged_edge_probability > 0.0) {
    RaggedEdges(options, texture_rng, near_doors, labels);
  }
  if (textured && options.speckle_per_m2 > 0.0) {
    Rng speckle_rng(options.seed ^ 0x94d049bb133111ebULL);
    Speckle(options, cells, speckle_rng, layout->building, around_doors, labels);
  }
  if (options.robot_width_m > 0.0) {
    FillRobotPockets(cells.Cells(options.robot_width_m / 2.0), start_cell, labels);
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
  for (const Room& room : layout->rooms) {
    for (const Door& door : room.doors) {
      const bool along_x = RunsAlongX(door.side);
      const cv::Point middle(door.opening.x + door.opening.width / 2,
                             door.opening.y + door.opening.height / 2);
      const Point2d at = world.grid.CellCenter({middle.x, middle.y});
      world.doors.push_back({at.x_m, at.y_m,
                             cells.Meters(along_x ? door.opening.width : door.opening.height),
                             along_x});
    }
  }
  world.room_floor_area_m2 = cells.SquareMeters(floor_cells);
  world.furniture_footprint_m2 = cells.SquareMeters(footprint_cells);
  const cv::Mat furniture = labels == kFurnitureLabel;
  world.furniture_area_m2 = cells.SquareMeters(cv::countNonZero(furniture));
  world.furniture_cells.assign(furniture.total(), 0);
  for (int row = 0; row < furniture.rows; ++row) {
    for (int col = 0; col < furniture.cols; ++col) {
      world.furniture_cells[std::size_t(row) * furniture.cols + col] =
          furniture.at<uint8_t>(row, col) ? 1 : 0;
    }
  }
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
  Require(o.door_width_min_m >= 0.7 - 1e-9, "door_width_min_m", o.door_width_min_m,
          "must be at least 0.7 m");
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
        {"furniture_fill", o.furniture_fill},
        {"clutter_fill", o.clutter_fill},
        {"table_legs_probability", o.table_legs_probability},
        {"chair_legs_probability", o.chair_legs_probability},
        {"shelving_hall_probability", o.shelving_hall_probability},
        {"alcove_probability", o.alcove_probability},
        {"dead_end_probability", o.dead_end_probability},
        {"corner_cut_probability", o.corner_cut_probability},
        {"ragged_edge_probability", o.ragged_edge_probability}}) {
    Require(value >= 0.0 && value <= 1.0, name, value, "must be in [0, 1]");
  }
  Require(o.passage_width_m >= 0.4 && o.passage_width_m <= o.door_width_min_m - 0.1 + 1e-9,
          "passage_width_m", o.passage_width_m,
          "must be in [0.4 m, door_width_min_m - 0.1 m] so every door passes it");
  Require(o.room_coverage_min >= 0.5 && o.room_coverage_min <= 1.0, "room_coverage_min",
          o.room_coverage_min, "must be in [0.5, 1]");
  Require(o.chairs_per_desk >= 0.0 && o.chairs_per_desk <= 4.0, "chairs_per_desk",
          o.chairs_per_desk, "must be in [0, 4]");
  Require(o.plants_per_100m2 >= 0.0 && o.plants_per_100m2 <= 20.0, "plants_per_100m2",
          o.plants_per_100m2, "must be in [0, 20]");
  Require(o.speckle_per_m2 >= 0.0 && o.speckle_per_m2 <= 2.0, "speckle_per_m2", o.speckle_per_m2,
          "must be in [0, 2]");
  Require(o.hall_door_spacing_m == 0.0 || o.hall_door_spacing_m >= 4.0, "hall_door_spacing_m",
          o.hall_door_spacing_m, "must be 0 (one door per hall side) or at least 4 m");
  Require(o.robot_width_m == 0.0 ||
              (o.robot_width_m >= 0.3 && o.robot_width_m <= o.passage_width_m + 1e-9),
          "robot_width_m", o.robot_width_m, "must be 0 (off) or in [0.3 m, passage_width_m]");
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
  if (text == "cluttered_office") return WorldStyle::kClutteredOffice;
  if (text == "warehouse") return WorldStyle::kWarehouse;
  throw std::invalid_argument("unknown world style '" + text +
                              "' (campus, office, test, cluttered_office or warehouse)");
}

std::string WorldStyleName(WorldStyle style) {
  switch (style) {
    case WorldStyle::kCampus: return "campus";
    case WorldStyle::kOffice: return "office";
    case WorldStyle::kTest: return "test";
    case WorldStyle::kClutteredOffice: return "cluttered_office";
    case WorldStyle::kWarehouse: return "warehouse";
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
    case WorldStyle::kClutteredOffice:
      options.target_free_area_m2 = 1500.0;
      options.corridor_width_m = 1.6;
      options.door_width_min_m = 0.7;
      options.door_width_max_m = 0.9;
      options.room_width_min_m = 3.0;
      options.room_width_max_m = 5.5;
      options.room_depth_min_m = 3.5;
      options.room_depth_max_m = 5.5;
      options.block_length_m = 16.0;
      options.aspect_ratio = 1.4;
      options.outer_rooms_probability = 0.6;
      options.open_plan_probability = 0.35;
      options.through_room_probability = 0.1;
      options.side_door_probability = 0.25;
      options.hall_probability = 0.25;  // open-plan floors with desk clusters
      options.join_blocks_probability = 0.25;
      options.furniture_fill = 0.0;
      options.passage_width_m = 0.6;
      options.room_coverage_min = 0.85;
      options.clutter_fill = 0.22;
      options.table_legs_probability = 0.7;
      options.chairs_per_desk = 1.0;
      options.chair_legs_probability = 0.3;
      options.plants_per_100m2 = 1.5;
      options.hall_door_spacing_m = 8.0;
      options.alcove_probability = 0.15;
      options.dead_end_probability = 0.1;
      options.corner_cut_probability = 0.06;
      options.ragged_edge_probability = 0.35;
      options.speckle_per_m2 = 0.15;
      options.robot_width_m = 0.5;
      break;
    case WorldStyle::kWarehouse:
      options.target_free_area_m2 = 2500.0;
      options.corridor_width_m = 2.6;  // main aisles
      options.door_width_min_m = 0.8;
      options.door_width_max_m = 1.0;
      options.room_width_min_m = 3.5;
      options.room_width_max_m = 6.0;
      options.room_depth_min_m = 5.0;
      options.room_depth_max_m = 9.0;
      options.block_length_m = 22.0;
      options.aspect_ratio = 1.3;
      options.outer_rooms_probability = 0.5;
      options.open_plan_probability = 0.3;
      options.through_room_probability = 0.15;
      options.side_door_probability = 0.25;
      options.hall_probability = 0.7;
      options.join_blocks_probability = 0.3;
      options.furniture_fill = 0.0;
      options.passage_width_m = 0.6;
      options.room_coverage_min = 0.8;
      options.clutter_fill = 0.2;
      options.table_legs_probability = 0.6;
      options.chairs_per_desk = 0.6;
      options.chair_legs_probability = 0.3;
      options.plants_per_100m2 = 0.3;
      options.shelving_hall_probability = 0.8;
      options.hall_door_spacing_m = 7.0;
      options.alcove_probability = 0.1;
      options.dead_end_probability = 0.1;
      options.corner_cut_probability = 0.05;
      options.ragged_edge_probability = 0.4;
      options.speckle_per_m2 = 0.2;
      options.robot_width_m = 0.5;
      break;
  }
  return options;
}

GeneratedWorld GenerateWorld(const WorldgenOptions& options) {
  Validate(options);
  const CellSizes cells(options);
  const cv::Mat disk = PassageDisk(options, cells);
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
  // Absent in worlds written before these options existed: there they were off.
  if (Textured(options)) {
    const std::vector<std::pair<const char*, double>> clutter = {
        {"passage_width_m", options.passage_width_m},
        {"room_coverage_min", options.room_coverage_min},
        {"clutter_fill", options.clutter_fill},
        {"table_legs_probability", options.table_legs_probability},
        {"chairs_per_desk", options.chairs_per_desk},
        {"chair_legs_probability", options.chair_legs_probability},
        {"plants_per_100m2", options.plants_per_100m2},
        {"shelving_hall_probability", options.shelving_hall_probability},
        {"hall_door_spacing_m", options.hall_door_spacing_m},
        {"alcove_probability", options.alcove_probability},
        {"dead_end_probability", options.dead_end_probability},
        {"corner_cut_probability", options.corner_cut_probability},
        {"ragged_edge_probability", options.ragged_edge_probability},
        {"speckle_per_m2", options.speckle_per_m2},
        {"robot_width_m", options.robot_width_m}};
    for (const auto& [key, value] : clutter) yaml << YAML::Key << key << YAML::Value << value;
  }
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
         << " m; free 0, walls and furniture 100, outside the building unknown.\n\n";
  if (Textured(options)) {
    readme << "Clutter and lidar-map texture: furniture stands on "
           << FormatNumber(std::round(world.furniture_footprint_m2)) << " m² of "
           << FormatNumber(std::round(world.room_floor_area_m2))
           << " m² of room floor (tables on legs and chairs counted whole; "
           << FormatNumber(std::round(world.furniture_area_m2))
           << " m² of it occupied cells); doors, alcoves, dead ends, cut corners, ragged walls "
              "and speckle as in `generator`. Free space a "
           << FormatNumber(options.robot_width_m)
           << " m wide disk cannot reach from the start is filled solid.\n\n";
  }
  readme << "Regenerate (from the repository root, with the built tool on the PATH):\n\n"
         << "    " << regenerate_command << "\n";
  readme.close();
  if (!readme) throw std::runtime_error(readme_path.string() + ": cannot write");
}

}  // namespace aslam
