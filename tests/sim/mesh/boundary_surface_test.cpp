#include "sim/mesh/boundary_surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "sim/mesh/box_mesher.h"

namespace incise::sim {
namespace {

const Vec3 kSize(0.03, 0.02, 0.05);  // [m]
const Vec3i kCells(3, 2, 4);

// Twice the area vector of face f over vertex positions V.
Vec3 area_vector(const BoundarySurface& surface, const Points& V, Eigen::Index f) {
  const Vec3 a = row3(V, surface.faces(f, 0));
  return (row3(V, surface.faces(f, 1)) - a).cross(row3(V, surface.faces(f, 2)) - a);
}

TEST(BoundarySurface, BoxSurfaceHasTheBoxNodesAndTwoTrianglesPerCellFace) {
  const TetMesh mesh = make_box_mesh(kSize, kCells);
  const BoundarySurface surface = boundary_surface(mesh);
  // The nodes on the box's faces: all but the (nx - 1)(ny - 1)(nz - 1) interior grid nodes.
  EXPECT_EQ(surface.nodes.size(), 4u * 3u * 5u - 2u * 1u * 3u);
  EXPECT_TRUE(std::is_sorted(surface.nodes.begin(), surface.nodes.end()));
  for (const int i : surface.nodes) {
    const Vec3 p = row3(mesh.rest, i);
    const bool on_face = (p.array() == 0).any() || (p.array() == kSize.array()).any();
    EXPECT_TRUE(on_face) << "node " << i;
  }
  EXPECT_EQ(surface.faces.rows(), 2 * 2 * (3 * 2 + 2 * 4 + 3 * 4));
  EXPECT_GE(surface.faces.minCoeff(), 0);
  EXPECT_LT(surface.faces.maxCoeff(), static_cast<int>(surface.nodes.size()));
}

TEST(BoundarySurface, IsClosedConsistentlyOrientedAndASphere) {
  const BoundarySurface surface = boundary_surface(make_box_mesh(kSize, kCells));
  // Closed and consistently oriented: every directed edge occurs once and its reverse once.
  std::map<std::pair<int, int>, int> directed;
  for (Eigen::Index f = 0; f < surface.faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      ++directed[{surface.faces(f, c), surface.faces(f, (c + 1) % 3)}];
  }
  std::set<std::pair<int, int>> edges;
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
    edges.insert(std::minmax(edge.first, edge.second));
  }
  const auto V = static_cast<Eigen::Index>(surface.nodes.size());
  const auto E = static_cast<Eigen::Index>(edges.size());
  EXPECT_EQ(V - E + surface.faces.rows(), 2);  // Euler characteristic of a sphere
}

TEST(BoundarySurface, EnclosesTheBoxVolumeWithOutwardFaces) {
  const TetMesh mesh = make_box_mesh(kSize, kCells);
  const BoundarySurface surface = boundary_surface(mesh);
  Points V, N;
  surface_vertices(surface, mesh.rest, V, N);
  // Divergence theorem with div(x) = 3: volume = sum over faces of a . ((b - a) x (c - a)) / 6,
  // positive only if every face normal points outwards.
  Real volume = 0;
  for (Eigen::Index f = 0; f < surface.faces.rows(); ++f) {
    volume += row3(V, surface.faces(f, 0)).dot(area_vector(surface, V, f)) / 6;
  }
  EXPECT_NEAR(volume, kSize.prod(), 1e-15);
}

// Each face records its tet: the face's nodes are three of the tet's, and the fourth lies behind
// the face's outward normal.
TEST(BoundarySurface, EachFaceKnowsTheTetItBounds) {
  const TetMesh mesh = make_box_mesh(kSize, kCells);
  const BoundarySurface surface = boundary_surface(mesh);
  ASSERT_EQ(surface.tets.size(), static_cast<std::size_t>(surface.faces.rows()));
  for (Eigen::Index f = 0; f < surface.faces.rows(); ++f) {
    const int t = surface.tets[static_cast<std::size_t>(f)];
    ASSERT_GE(t, 0);
    ASSERT_LT(t, mesh.num_tets());
    std::set<int> tet_nodes;
    for (int k = 0; k < 4; ++k)
      tet_nodes.insert(mesh.tets(t, k));
    Vec3 corners[3];
    for (int c = 0; c < 3; ++c) {
      const int node = surface.nodes[static_cast<std::size_t>(surface.faces(f, c))];
      EXPECT_EQ(tet_nodes.erase(node), 1u) << "face " << f << " is not a face of tet " << t;
      corners[c] = row3(mesh.rest, node);
    }
    ASSERT_EQ(tet_nodes.size(), 1u);
    const Vec3 normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
    EXPECT_LT(normal.dot(row3(mesh.rest, *tet_nodes.begin()) - corners[0]), 0) << "face " << f;
  }
}

TEST(SurfaceVertices, CopiesPositionsAndGivesFaceNormalsOnFlatFaces) {
  const TetMesh mesh = make_box_mesh(kSize, kCells);
  const BoundarySurface surface = boundary_surface(mesh);
  Points V, N;
  surface_vertices(surface, mesh.rest, V, N);
  ASSERT_EQ(V.rows(), static_cast<Eigen::Index>(surface.nodes.size()));
  ASSERT_EQ(N.rows(), V.rows());
  int top_inner = 0;
  for (std::size_t j = 0; j < surface.nodes.size(); ++j) {
    const auto row = static_cast<Eigen::Index>(j);
    EXPECT_EQ(row3(V, static_cast<int>(row)), row3(mesh.rest, surface.nodes[j]));
    EXPECT_NEAR(N.row(row).norm(), 1, 1e-14);
    const Vec3 p = row3(V, static_cast<int>(row));
    const bool inside_top =
        p.z() == kSize.z() && p.x() > 0 && p.x() < kSize.x() && p.y() > 0 && p.y() < kSize.y();
    if (inside_top) {
      ++top_inner;
      EXPECT_LT((row3(N, static_cast<int>(row)) - Vec3::UnitZ()).norm(), 1e-14);
    }
  }
  EXPECT_EQ(top_inner, 2 * 1);  // the (nx - 1)(ny - 1) inner nodes of the top face
  // A box corner's normal, with faces of different sizes around it, still points outwards.
  const Vec3 corner_normal = row3(N, 0);  // node 0 is the origin
  EXPECT_TRUE((corner_normal.array() < 0).all());
}

TEST(SurfaceVertices, NormalsTurnWithARigidRotationAndBuffersAreReused) {
  const TetMesh mesh = make_box_mesh(kSize, kCells);
  const BoundarySurface surface = boundary_surface(mesh);
  Points V, N;
  surface_vertices(surface, mesh.rest, V, N);
  const Points N0 = N;
  const Real* v_data = V.data();
  const Real* n_data = N.data();
  const Mat3 R = Eigen::AngleAxis<Real>(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Points x = (mesh.rest * R.transpose()).rowwise() + Vec3(0.1, -0.2, 0.3).transpose();
  surface_vertices(surface, x, V, N);
  EXPECT_EQ(V.data(), v_data);
  EXPECT_EQ(N.data(), n_data);
  for (Eigen::Index j = 0; j < N.rows(); ++j) {
    EXPECT_LT((row3(N, static_cast<int>(j)) - R * row3(N0, static_cast<int>(j))).norm(), 1e-13);
  }
}

TEST(SurfaceVertices, CollapsedSurfaceHasZeroNormalsNotNaN) {
  const TetMesh mesh = make_box_mesh(kSize, kCells);
  const BoundarySurface surface = boundary_surface(mesh);
  Points V, N;
  surface_vertices(surface, Points::Zero(mesh.num_nodes(), 3), V, N);
  EXPECT_TRUE(N.isZero(0));
}

// The tracker's surface equals a fresh extraction through a run of local changes: tets split at
// their centroids (slot t keeps one child, three are appended), and one tet taken out of the mesh
// by giving its slot the nodes of a detached copy (a crack opening).
void expect_same(const BoundarySurface& a, const BoundarySurface& b, int change) {
  ASSERT_EQ(a.nodes, b.nodes) << "change " << change;
  ASSERT_EQ(a.tets, b.tets) << "change " << change;
  ASSERT_TRUE(a.faces == b.faces) << "change " << change;
}

TEST(BoundaryTracker, FollowsLocalChangesFaceForFace) {
  TetMesh mesh = make_box_mesh(kSize, kCells);
  BoundaryTracker tracker(mesh.tets);
  expect_same(tracker.surface(mesh.num_nodes()), boundary_surface(mesh), -1);
  std::vector<int> changed;
  for (int change = 0; change < 40; ++change) {
    changed.clear();
    const int t = (change * 37) % static_cast<int>(mesh.tets.rows());
    const std::array<int, 4> n{mesh.tets(t, 0), mesh.tets(t, 1), mesh.tets(t, 2), mesh.tets(t, 3)};
    const int first_new = mesh.num_nodes();
    if (change % 5 == 4) {
      // Detach tet t: its slot gets four new nodes at the same places.
      mesh.rest.conservativeResize(first_new + 4, 3);
      for (int k = 0; k < 4; ++k) {
        mesh.rest.row(first_new + k) = mesh.rest.row(n[static_cast<std::size_t>(k)]);
        mesh.tets(t, k) = first_new + k;
      }
      changed.push_back(t);
    } else {
      // Split at the centroid c: (c, 1, 2, 3), (0, c, 2, 3), (0, 1, c, 3), (0, 1, 2, c) keep the
      // orientation.
      mesh.rest.conservativeResize(first_new + 1, 3);
      Vec3 centre = Vec3::Zero();
      for (const int v : n)
        centre += row3(mesh.rest, v) / 4;
      mesh.rest.row(first_new) = centre.transpose();
      const auto rows = mesh.tets.rows();
      mesh.tets.conservativeResize(rows + 3, 4);
      for (int k = 0; k < 4; ++k) {
        std::array<int, 4> child = n;
        child[static_cast<std::size_t>(k)] = first_new;
        const auto row = k == 0 ? static_cast<Eigen::Index>(t) : rows + k - 1;
        for (int j = 0; j < 4; ++j)
          mesh.tets(row, j) = child[static_cast<std::size_t>(j)];
        changed.push_back(static_cast<int>(row));
      }
    }
    mesh.labels.conservativeResize(mesh.tets.rows());
    mesh.labels.setZero();
    tracker.update(mesh.tets, changed);
    expect_same(tracker.surface(mesh.num_nodes()), boundary_surface(mesh), change);
  }
}

TEST(BoundaryTracker, RefusesAFaceSharedByThreeTetsAndAShrinkingMesh) {
  const TetMesh mesh = make_box_mesh(kSize, kCells);
  Tets three(3, 4);
  three << 0, 1, 2, 3,  //
      0, 1, 2, 4,       //
      0, 1, 2, 5;
  EXPECT_THROW(BoundaryTracker{three}, std::invalid_argument);
  BoundaryTracker tracker(mesh.tets);
  const Tets fewer = mesh.tets.topRows(mesh.tets.rows() - 1);
  EXPECT_THROW(tracker.update(fewer, {}), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim
