#include "frontier/frontier_lcm.h"

#include <cmath>
#include <unordered_set>

namespace aslam {
namespace {

bool Finite(Point2d p) { return std::isfinite(p.x_m) && std::isfinite(p.y_m); }

}  // namespace

frontier_list_t ToLcm(const FrontierList& list) {
  frontier_list_t msg{};
  msg.utime = list.utime;
  msg.map_revision = list.map_revision;
  msg.num_frontiers = static_cast<int32_t>(list.frontiers.size());
  msg.frontiers.reserve(list.frontiers.size());
  for (const Frontier& f : list.frontiers) {
    frontier_t out{};
    out.id = f.id;
    out.size_cells = f.size_cells();
    out.centroid_x_m = f.centroid_m.x_m;
    out.centroid_y_m = f.centroid_m.y_m;
    out.target_x_m = f.target_m.x_m;
    out.target_y_m = f.target_m.y_m;
    out.num_points = static_cast<int32_t>(f.points_m.size());
    out.point_x_m.reserve(f.points_m.size());
    out.point_y_m.reserve(f.points_m.size());
    for (const Point2d& p : f.points_m) {
      out.point_x_m.push_back(static_cast<float>(p.x_m));
      out.point_y_m.push_back(static_cast<float>(p.y_m));
    }
    msg.frontiers.push_back(std::move(out));
  }
  return msg;
}

// Also rejects negative or repeated ids (the utility keys goals and
// blacklists by id) and size_cells != num_points (Frontier derives its size
// from its points).
std::optional<FrontierList> FromLcm(const frontier_list_t& msg) {
  if (msg.num_frontiers < 0 ||
      static_cast<std::size_t>(msg.num_frontiers) != msg.frontiers.size()) {
    return std::nullopt;
  }
  FrontierList list;
  list.utime = msg.utime;
  list.map_revision = msg.map_revision;
  list.frontiers.reserve(msg.frontiers.size());
  std::unordered_set<int32_t> ids;
  for (const frontier_t& in : msg.frontiers) {
    if (in.id < 0 || !ids.insert(in.id).second) return std::nullopt;
    if (in.num_points < 0 || static_cast<std::size_t>(in.num_points) != in.point_x_m.size() ||
        in.point_x_m.size() != in.point_y_m.size() || in.size_cells != in.num_points) {
      return std::nullopt;
    }
    Frontier f;
    f.id = in.id;
    f.centroid_m = {in.centroid_x_m, in.centroid_y_m};
    f.target_m = {in.target_x_m, in.target_y_m};
    if (!Finite(f.centroid_m) || !Finite(f.target_m)) return std::nullopt;
    f.points_m.reserve(in.point_x_m.size());
    for (std::size_t i = 0; i < in.point_x_m.size(); ++i) {
      const Point2d p{in.point_x_m[i], in.point_y_m[i]};
      if (!Finite(p)) return std::nullopt;
      f.points_m.push_back(p);
    }
    list.frontiers.push_back(std::move(f));
  }
  return list;
}

}  // namespace aslam
