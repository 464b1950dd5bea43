#include "slam/g2o_io.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <Eigen/Cholesky>

#include "common/atomic_file.h"

namespace aslam {
namespace {

[[noreturn]] void Fail(const std::string& path, int line, const std::string& what) {
  throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
}

// Reads exactly `count` finite numbers and nothing else from the rest of the line.
std::vector<double> ReadNumbers(std::istringstream& in, int count, const std::string& path,
                                int line, const std::string& tag) {
  std::vector<double> values(count);
  for (double& value : values) {
    std::string token;
    if (!(in >> token)) {
      Fail(path, line, tag + " needs " + std::to_string(count) + " numbers");
    }
    std::size_t used = 0;
    try {
      value = std::stod(token, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != token.size() || !std::isfinite(value)) {
      Fail(path, line, "bad number '" + token + "' in " + tag);
    }
  }
  std::string extra;
  if (in >> extra) Fail(path, line, "unexpected '" + extra + "' after " + tag);
  return values;
}

int ToId(double value, const std::string& path, int line) {
  if (value != std::floor(value) || value < 0 || value > std::numeric_limits<int>::max()) {
    Fail(path, line, "bad vertex id");
  }
  return static_cast<int>(value);
}

}  // namespace

void WriteG2o(const PoseGraph& graph, const std::string& path) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);  // exact round trip
  for (const PoseGraphNode& node : graph.nodes) {
    out << "VERTEX_SE2 " << node.id << ' ' << node.pose.x_m << ' ' << node.pose.y_m << ' '
        << node.pose.yaw_rad << '\n';
  }
  for (const PoseGraphEdge& edge : graph.edges) {
    const Eigen::Matrix3d& I = edge.information;
    out << "EDGE_SE2 " << edge.from_id << ' ' << edge.to_id << ' ' << edge.measurement.x_m << ' '
        << edge.measurement.y_m << ' ' << edge.measurement.yaw_rad << ' ' << I(0, 0) << ' '
        << I(0, 1) << ' ' << I(0, 2) << ' ' << I(1, 1) << ' ' << I(1, 2) << ' ' << I(2, 2) << '\n';
  }
  WriteFileAtomically(path, out.str());
}

PoseGraph ReadG2o(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open for reading");

  std::map<int, PoseGraphNode> nodes;
  std::vector<std::pair<int, PoseGraphEdge>> edges;  // with the line, for errors
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    std::istringstream fields(text);
    std::string tag;
    if (!(fields >> tag) || tag[0] == '#') continue;  // blank line or comment
    if (tag == "VERTEX_SE2") {
      const std::vector<double> v = ReadNumbers(fields, 4, path, line, tag);
      PoseGraphNode node;
      node.id = ToId(v[0], path, line);
      node.pose = {v[1], v[2], v[3]};
      if (!nodes.emplace(node.id, node).second) {
        Fail(path, line, "duplicate vertex " + std::to_string(node.id));
      }
    } else if (tag == "EDGE_SE2") {
      const std::vector<double> v = ReadNumbers(fields, 11, path, line, tag);
      PoseGraphEdge edge;
      edge.from_id = ToId(v[0], path, line);
      edge.to_id = ToId(v[1], path, line);
      if (edge.from_id == edge.to_id) Fail(path, line, "edge connects a vertex to itself");
      edge.measurement = {v[2], v[3], v[4]};
      edge.information << v[5], v[6], v[7],  //
          v[6], v[8], v[9],                  //
          v[7], v[9], v[10];
      if (Eigen::LLT<Eigen::Matrix3d>(edge.information).info() != Eigen::Success) {
        Fail(path, line, "information matrix is not positive definite");
      }
      // The format has no edge kind: odometry links consecutive keyframes.
      edge.kind =
          std::abs(edge.to_id - edge.from_id) == 1 ? EdgeKind::kOdometry : EdgeKind::kLoopClosure;
      edges.emplace_back(line, edge);
    } else if (tag == "FIX") {
      continue;  // g2o's gauge hint; we always fix the first node
    } else {
      Fail(path, line, "unknown record '" + tag + "'");
    }
  }
  if (in.bad()) throw std::runtime_error(path + ": read failed");

  PoseGraph graph;
  graph.nodes.reserve(nodes.size());
  for (const auto& [id, node] : nodes) {
    if (id != static_cast<int>(graph.nodes.size())) {
      throw std::runtime_error(path + ": vertex ids must be 0.." +
                               std::to_string(nodes.size() - 1) + ", vertex " +
                               std::to_string(graph.nodes.size()) + " is missing");
    }
    graph.nodes.push_back(node);
  }
  graph.edges.reserve(edges.size());
  for (const auto& [edge_line, edge] : edges) {
    if (!nodes.count(edge.from_id) || !nodes.count(edge.to_id)) {
      Fail(path, edge_line, "edge refers to a missing vertex");
    }
    graph.edges.push_back(edge);
  }
  return graph;
}

}  // namespace aslam
