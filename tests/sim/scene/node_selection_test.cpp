#include "sim/scene/node_selection.h"

#include <gtest/gtest.h>

#include <vector>

#include "sim/mesh/box_mesher.h"

namespace incise::sim {
namespace {

TEST(SelectionTolerance, IsAMillionthOfTheBoundingBoxDiagonal) {
  Points points(2, 3);
  points << 1, 1, 1, 4, 5, 1;  // diagonal 5
  EXPECT_DOUBLE_EQ(selection_tolerance(points), 5e-6);
  EXPECT_EQ(selection_tolerance(Points(0, 3)), 0);
}

TEST(NodesInBox, BoxIsClosedAndWidenedByTheTolerance) {
  Points points(4, 3);
  points << 0, 0, 0, 1, 0, 0, 1 + 1e-7, 0, 0, 1 + 1e-5, 0, 0;
  const Box3 box(Vec3(0, 0, 0), Vec3(1, 0, 0));
  EXPECT_EQ(nodes_in_box(points, box, 0), (std::vector<int>{0, 1}));
  EXPECT_EQ(nodes_in_box(points, box, 1e-6), (std::vector<int>{0, 1, 2}));
  EXPECT_TRUE(nodes_in_box(points, Box3(Vec3(2, 0, 0), Vec3(3, 1, 1)), 1e-6).empty());
}

TEST(NodesInBox, FaceOfABoxMeshPicksExactlyItsGridNodes) {
  // Interior grid lines are at 0.1 / 3 multiples, which are not exact in binary.
  const TetMesh mesh = make_box_mesh(Vec3(0.1, 0.1, 0.1), Vec3i(3, 3, 3));
  const Real tolerance = selection_tolerance(mesh.rest);
  EXPECT_EQ(nodes_in_box(mesh.rest, Box3(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0)), tolerance).size(), 16u);
  const std::vector<int> line =
      nodes_in_box(mesh.rest, Box3(Vec3(0.1 / 3, 0, 0), Vec3(0.1 / 3, 0.1, 0)), tolerance);
  EXPECT_EQ(line, (std::vector<int>{1, 5, 9, 13}));
}

}  // namespace
}  // namespace incise::sim
