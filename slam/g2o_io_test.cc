#include "slam/g2o_io.h"

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "common/test_temp_dir.h"

namespace aslam {
namespace {

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

// The message of the runtime_error ReadG2o throws, or "" if it does not throw.
std::string ReadError(const std::string& text) {
  const std::string path = TestTempPath("bad.g2o");
  WriteText(path, text);
  try {
    ReadG2o(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(G2oIoTest, RoundTripIsExact) {
  PoseGraph graph;
  for (int i = 0; i < 5; ++i) {
    graph.nodes.push_back({i, 0, {0.1 * i + 1.0 / 3.0, -std::sqrt(2.0) * i, WrapAngle(1.1 * i)}});
  }
  for (int i = 0; i < 4; ++i) {
    PoseGraphEdge edge;
    edge.from_id = i;
    edge.to_id = i + 1;
    edge.measurement = {0.3 + 1e-9 * i, -0.01, M_PI / 7};
    edge.information << 100.0 + i, 1.5, -0.25, 1.5, 90.0, 0.125, -0.25, 0.125, 400.0 / 3.0;
    graph.edges.push_back(edge);
  }
  PoseGraphEdge closure;
  closure.from_id = 4;
  closure.to_id = 0;
  closure.kind = EdgeKind::kLoopClosure;
  closure.measurement = {-1.0, 2.0, -3.0};
  graph.edges.push_back(closure);

  const std::string path = TestTempPath("round_trip.g2o");
  WriteG2o(graph, path);
  const PoseGraph read = ReadG2o(path);

  ASSERT_EQ(read.nodes.size(), graph.nodes.size());
  for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
    EXPECT_EQ(read.nodes[i].id, graph.nodes[i].id);
    EXPECT_EQ(read.nodes[i].pose.x_m, graph.nodes[i].pose.x_m);
    EXPECT_EQ(read.nodes[i].pose.y_m, graph.nodes[i].pose.y_m);
    EXPECT_EQ(read.nodes[i].pose.yaw_rad, graph.nodes[i].pose.yaw_rad);
  }
  ASSERT_EQ(read.edges.size(), graph.edges.size());
  for (std::size_t i = 0; i < graph.edges.size(); ++i) {
    const PoseGraphEdge& a = read.edges[i];
    const PoseGraphEdge& b = graph.edges[i];
    EXPECT_EQ(a.from_id, b.from_id);
    EXPECT_EQ(a.to_id, b.to_id);
    EXPECT_EQ(a.kind, b.kind) << "edge " << i;
    EXPECT_EQ(a.measurement.x_m, b.measurement.x_m);
    EXPECT_EQ(a.measurement.y_m, b.measurement.y_m);
    EXPECT_EQ(a.measurement.yaw_rad, b.measurement.yaw_rad);
    EXPECT_EQ(a.information, b.information) << "edge " << i;
  }
}

TEST(G2oIoTest, ReadsTheStandardFormatWithCommentsBlankLinesAndAnyVertexOrder) {
  const std::string path = TestTempPath("standard.g2o");
  WriteText(path,
            "# a comment\n"
            "VERTEX_SE2 1 1.0 0.0 0.5\n"
            "\n"
            "VERTEX_SE2 0 0 0 0\n"
            "VERTEX_SE2 2 2 0 0\n"
            "FIX 0\n"
            "EDGE_SE2 0 1 1 0 0.5 50 2 3 40 4 30\n"
            "EDGE_SE2 2 0 -2 0 0 1 0 0 1 0 1\n");
  const PoseGraph graph = ReadG2o(path);
  ASSERT_EQ(graph.nodes.size(), 3u);
  EXPECT_EQ(graph.nodes[1].pose.yaw_rad, 0.5);
  ASSERT_EQ(graph.edges.size(), 2u);
  Eigen::Matrix3d expected;
  expected << 50, 2, 3, 2, 40, 4, 3, 4, 30;
  EXPECT_EQ(graph.edges[0].information, expected);
  EXPECT_EQ(graph.edges[0].kind, EdgeKind::kOdometry);
  EXPECT_EQ(graph.edges[1].kind, EdgeKind::kLoopClosure);
}

TEST(G2oIoTest, MalformedLinesNameThePathAndLine) {
  const std::string path = TestTempPath("bad.g2o");
  const std::string header = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";
  const std::string at_line_3 = path + ":3:";
  struct Case {
    const char* line;
    const char* detail;
  };
  for (const Case& c : {
           Case{"VERTEX_SE2 2 1 0\n", "needs 4 numbers"},
           Case{"VERTEX_SE2 2 1 0 zero\n", "bad number 'zero'"},
           Case{"VERTEX_SE2 2 1 0 nan\n", "bad number 'nan'"},
           Case{"VERTEX_SE2 2 1 0 0 7\n", "unexpected '7'"},
           Case{"VERTEX_SE2 1.5 1 0 0\n", "bad vertex id"},
           Case{"VERTEX_SE2 1 1 0 0\n", "duplicate vertex 1"},
           Case{"EDGE_SE2 0 1 1 0 0 1 0 0 1 0\n", "needs 11 numbers"},
           Case{"EDGE_SE2 0 1 1 0 0 1 0 0 1 0 -1\n", "not positive definite"},
           Case{"EDGE_SE2 0 0 1 0 0 1 0 0 1 0 1\n", "to itself"},
           Case{"EDGE_SE2 0 5 1 0 0 1 0 0 1 0 1\n", "missing vertex"},
           Case{"EDGE_SE3:QUAT 0 1\n", "unknown record"},
       }) {
    const std::string message = ReadError(header + c.line + "VERTEX_SE2 2 2 0 0\n");
    EXPECT_NE(message.find(at_line_3), std::string::npos) << c.line << " -> " << message;
    EXPECT_NE(message.find(c.detail), std::string::npos) << c.line << " -> " << message;
  }
}

TEST(G2oIoTest, MissingVertexIdsAndUnreadableFilesThrow) {
  EXPECT_NE(ReadError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 2 0 0 0\n").find("vertex 1 is missing"),
            std::string::npos);
  EXPECT_THROW(ReadG2o(TestTempPath("does_not_exist.g2o")), std::runtime_error);
  EXPECT_THROW(WriteG2o(PoseGraph{}, "/nonexistent_dir/x.g2o"), std::runtime_error);
}

}  // namespace
}  // namespace aslam
