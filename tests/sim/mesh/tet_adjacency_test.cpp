#include "sim/mesh/tet_adjacency.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <stdexcept>

#include "sim/mesh/box_mesher.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {
namespace {

// Two positively oriented tets glued on face (0, 1, 2): apexes 3 above and 4 below.
struct Bipyramid {
  Points points;
  Tets tets;
};

Bipyramid bipyramid() {
  Bipyramid b;
  b.points.resize(5, 3);
  b.points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 1, 0.2, 0.2, -1;
  b.tets.resize(2, 4);
  b.tets << 0, 1, 2, 3, 0, 2, 1, 4;
  return b;
}

Vec3 area_vector(const Points& p, int a, int b, int c) {
  return (row3(p, b) - row3(p, a)).cross(row3(p, c) - row3(p, a)) / 2;
}

TEST(UniqueEdges, SingleTetHasSixSortedEdges) {
  Tets tet(1, 4);
  tet << 3, 0, 2, 1;
  const Edges edges = unique_edges(tet);
  Edges expected(6, 2);
  expected << 0, 1, 0, 2, 0, 3, 1, 2, 1, 3, 2, 3;
  EXPECT_EQ(edges, expected);
}

TEST(UniqueEdges, TwoTetsOnAFaceShareThreeEdges) {
  EXPECT_EQ(unique_edges(bipyramid().tets).rows(), 9);
}

TEST(TetEdgeIndices, MapsEveryLocalEdgeToItsRow) {
  const Tets tets = bipyramid().tets;
  const Edges edges = unique_edges(tets);
  const TetEdgeIndices indices = tet_edge_indices(tets, edges);
  for (int t = 0; t < 2; ++t) {
    for (int e = 0; e < 6; ++e) {
      const int a = tets(t, kTetEdges[e][0]);
      const int b = tets(t, kTetEdges[e][1]);
      EXPECT_EQ(edges(indices(t, e), 0), std::min(a, b));
      EXPECT_EQ(edges(indices(t, e), 1), std::max(a, b));
    }
  }
  Edges missing = edges.topRows(8);
  EXPECT_THROW(tet_edge_indices(tets, missing), std::invalid_argument);
}

TEST(NodeTets, ListsTheTetsAroundEachNode) {
  const NodeTets around = node_tets(bipyramid().tets, 6);  // node 5 is unused
  const std::vector<int> offsets = {0, 2, 4, 6, 7, 8, 8};
  const std::vector<int> tets = {0, 1, 0, 1, 0, 1, 0, 1};
  EXPECT_EQ(around.offsets, offsets);
  EXPECT_EQ(around.tets, tets);
}

TEST(FaceNeighbours, GluedTetsSeeEachOtherAcrossTheSharedFaceOnly) {
  const Tets neighbours = face_neighbours(bipyramid().tets);
  // The shared face (0, 1, 2) is opposite local node 3 in both tets.
  Tets expected(2, 4);
  expected << -1, -1, -1, 1, -1, -1, -1, 0;
  EXPECT_EQ(neighbours, expected);
}

TEST(FaceNeighbours, RejectsAFaceSharedByThreeTets) {
  Tets tets(3, 4);
  tets << 0, 1, 2, 3, 0, 2, 1, 4, 0, 1, 2, 5;
  EXPECT_THROW(face_neighbours(tets), std::invalid_argument);
  EXPECT_THROW(boundary_faces(tets), std::invalid_argument);
}

TEST(BoundaryFaces, SingleTetFacesPointOutwards) {
  Points points(4, 3);
  points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Tets tet(1, 4);
  tet << 0, 1, 2, 3;
  const Triangles faces = boundary_faces(tet);
  ASSERT_EQ(faces.rows(), 4);
  const Vec3 centroid = points.colwise().mean().transpose();
  for (int f = 0; f < 4; ++f) {
    const Vec3 n = area_vector(points, faces(f, 0), faces(f, 1), faces(f, 2));
    EXPECT_GT(n.dot(row3(points, faces(f, 0)) - centroid), 0) << "face " << f;
  }
}

// Identities that hold on any conforming mesh of a ball; checked on box meshes whose nodes are
// jittered so that nothing depends on the grid's regularity.
class AdjacencyOnJitteredBoxes : public ::testing::TestWithParam<Vec3i> {
 protected:
  TetMesh mesh_ = make_jittered_box(GetParam());

  static TetMesh make_jittered_box(const Vec3i& cells) {
    TetMesh mesh = make_box_mesh(Vec3(0.3, 0.2, 0.25), cells);
    std::mt19937 random(42);
    std::uniform_real_distribution<Real> jitter(-0.01, 0.01);  // well below the cell size
    for (Eigen::Index i = 0; i < mesh.rest.rows(); ++i) {
      for (int a = 0; a < 3; ++a)
        mesh.rest(i, a) += jitter(random);
    }
    return mesh;
  }
};

TEST_P(AdjacencyOnJitteredBoxes, BoundaryIsClosedAndEnclosesTheVolume) {
  const Triangles faces = boundary_faces(mesh_.tets);
  Vec3 area_sum = Vec3::Zero();
  Real enclosed = 0;  // divergence theorem: V = sum over faces of (centroid . area) / 3
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Vec3 area = area_vector(mesh_.rest, faces(f, 0), faces(f, 1), faces(f, 2));
    const Vec3 centroid = (row3(mesh_.rest, faces(f, 0)) + row3(mesh_.rest, faces(f, 1)) +
                           row3(mesh_.rest, faces(f, 2))) /
                          3;
    area_sum += area;
    enclosed += centroid.dot(area) / 3;
  }
  EXPECT_LT(area_sum.norm(), 1e-14);
  EXPECT_NEAR(enclosed, total_volume(mesh_.rest, mesh_.tets), 1e-14);
}

TEST_P(AdjacencyOnJitteredBoxes, NeighboursAreMutualAndShareTheFaceNodes) {
  const Tets neighbours = face_neighbours(mesh_.tets);
  int boundary = 0;
  for (int t = 0; t < mesh_.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      const int n = neighbours(t, k);
      if (n < 0) {
        ++boundary;
        continue;
      }
      const int back =
          static_cast<int>(std::find(neighbours.row(n).data(), neighbours.row(n).data() + 4, t) -
                           neighbours.row(n).data());
      ASSERT_LT(back, 4) << "tet " << n << " does not see tet " << t;
      std::set<int> mine;
      std::set<int> theirs;
      for (int c = 0; c < 3; ++c) {
        mine.insert(mesh_.tets(t, kTetFaces[k][c]));
        theirs.insert(mesh_.tets(n, kTetFaces[back][c]));
      }
      EXPECT_EQ(mine, theirs);
    }
  }
  EXPECT_EQ(boundary, boundary_faces(mesh_.tets).rows());
}

TEST_P(AdjacencyOnJitteredBoxes, NodeTetsListEachTetUnderItsFourNodes) {
  const NodeTets around = node_tets(mesh_.tets, mesh_.num_nodes());
  ASSERT_EQ(around.tets.size(), static_cast<std::size_t>(4 * mesh_.num_tets()));
  for (int t = 0; t < mesh_.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      const int node = mesh_.tets(t, k);
      const auto begin = around.tets.begin() + around.offsets[static_cast<std::size_t>(node)];
      const auto end = around.tets.begin() + around.offsets[static_cast<std::size_t>(node) + 1];
      EXPECT_TRUE(std::binary_search(begin, end, t));
    }
  }
}

TEST_P(AdjacencyOnJitteredBoxes, EulerCharacteristicOfABallIsOne) {
  const Triangles boundary = boundary_faces(mesh_.tets);
  const Eigen::Index faces = (4 * mesh_.num_tets() + boundary.rows()) / 2;
  const Eigen::Index edges = unique_edges(mesh_.tets).rows();
  EXPECT_EQ(mesh_.num_nodes() - edges + faces - mesh_.num_tets(), 1);
}

INSTANTIATE_TEST_SUITE_P(Cells, AdjacencyOnJitteredBoxes,
                         ::testing::Values(Vec3i(1, 1, 1), Vec3i(2, 3, 4), Vec3i(5, 1, 2)));

}  // namespace
}  // namespace incise::sim
