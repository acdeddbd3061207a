// Simplification after cutting (sim/cut/simplify_cut.h): the quality measure's closed forms, the
// link condition on constructed cases (a collapse that would flatten a tet or pinch the boundary
// is refused, an interior one is allowed), and random plane cuts of a jittered box simplified:
// valid mesh, rest volume kept, the boundary still on the box and the cut plane, and no tet of
// the cut region below the stated bound.

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "cut_checks.h"
#include "sim/cut/cut_mesh.h"
#include "sim/cut/simplify_cut.h"
#include "sim/mesh/box_mesher.h"
#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::cut {
namespace {

// The bound reached on the cut region (stated in docs/cutting.md): every tet with a node on the
// crack has quality (smallest altitude / longest edge) at least this after simplification.
constexpr Real kQualityBound = 0.03;

TEST(SimplifyCut, QualityClosedForms) {
  // Regular tet: altitude sqrt(2/3) of the edge.
  const Vec3 a(1, 1, 1), b(1, -1, -1), c(-1, 1, -1), d(-1, -1, 1);
  EXPECT_NEAR(tet_quality(a, c, b, d), std::sqrt(2.0 / 3.0), 1e-12);
  EXPECT_NEAR(tet_quality(a, b, c, d), -std::sqrt(2.0 / 3.0), 1e-12);
  // A Kuhn simplex of the unit cube: volume 1/6, largest face sqrt(2)/2, longest edge sqrt(3).
  EXPECT_NEAR(tet_quality(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 1)),
              1 / std::sqrt(6.0), 1e-12);
  // Scale-free.
  EXPECT_NEAR(tet_quality(Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(3, 3, 0), Vec3(3, 3, 3)),
              1 / std::sqrt(6.0), 1e-12);
  EXPECT_EQ(tet_quality(a, a, c, d), 0);
}

TEST(SimplifyCut, LinkConditionRefusesPinchesAndAllowsInteriorCollapses) {
  // One tet: contracting an edge would flatten it (Knee Arthroscopy VR Fig. 20 (a), a face's hole
  // closing).
  Tets one(1, 4);
  one << 0, 1, 2, 3;
  EXPECT_FALSE(link_condition_holds(one, 0, 1));
  // A cube of 6 Kuhn tets around its diagonal (0,0,0)-(1,1,1): both ends are on the boundary but
  // the edge is interior: contracting it would pinch the surface at a point (Fig. 20 (b)).
  Points corners(8, 3);
  for (int i = 0; i < 8; ++i)
    corners.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  Tets cube(6, 4);
  const int axis[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  for (int t = 0; t < 6; ++t) {
    cube.row(t) << 0, axis[t][0], axis[t][0] + axis[t][1], 7;
    if (signed_volume(row3(corners, cube(t, 0)), row3(corners, cube(t, 1)),
                      row3(corners, cube(t, 2)), row3(corners, cube(t, 3))) < 0)
      std::swap(cube(t, 1), cube(t, 2));
  }
  ASSERT_EQ(testing::boundary_problem(cube), "");
  EXPECT_FALSE(link_condition_holds(cube, 0, 7));
  // A boundary edge of that cube, (0, 1): its collapse keeps the topology (a ball stays a ball).
  EXPECT_TRUE(link_condition_holds(cube, 0, 1));
  // A cube edge on the boundary (a face diagonal's neighbour): allowed.
  const TetMesh grid = make_box_mesh({2, 2, 2}, {2, 2, 2});
  int centre = -1, face_centre = -1;
  for (int i = 0; i < grid.num_nodes(); ++i) {
    if ((row3(grid.rest, i) - Vec3(1, 1, 1)).norm() < 1e-12) centre = i;
    if ((row3(grid.rest, i) - Vec3(1, 1, 0)).norm() < 1e-12) face_centre = i;
  }
  ASSERT_GE(centre, 0);
  ASSERT_GE(face_centre, 0);
  EXPECT_TRUE(link_condition_holds(grid.tets, centre, face_centre));
  // simplify_cut_region on the cube with the diagonal's tets as slivers: whatever it collapses,
  // the result stays a valid closed ball.
  TetMesh mesh = make_tet_mesh(corners, cube);
  const std::vector<int> all = {0, 1, 2, 3, 4, 5};
  const SimplifyReport s = simplify_cut_region(mesh, all, SimplifyOptions{0.9, 1e-9, 5});
  EXPECT_EQ(testing::boundary_problem(mesh.tets), "");
  EXPECT_NEAR(total_volume(mesh.rest, mesh.tets), 1, 1e-12);
  EXPECT_GT(s.rejected_topology + s.rejected_boundary + s.rejected_quality, 0);
}

TEST(SimplifyCut, RandomPlaneCutsSimplifiedKeepValidityVolumeAndBoundary) {
  std::mt19937 random(21);
  std::uniform_real_distribution<Real> unit(0, 1);
  std::normal_distribution<Real> normal(0, 1);
  int collapses = 0;
  for (int cut = 0; cut < 8; ++cut) {
    TetMesh mesh = testing::jittered_box({1, 1, 1}, {4, 4, 4}, 0.2, 30 + cut);
    const Real volume = total_volume(mesh.rest, mesh.tets);
    const Vec3 n = Vec3(normal(random), normal(random), normal(random)).normalized();
    const Vec3 point(0.3 + 0.4 * unit(random), 0.3 + 0.4 * unit(random), 0.3 + 0.4 * unit(random));
    const CutReport report = cut_mesh(mesh, testing::plane_blade(point, n, 3));
    const SimplifyReport s = simplify_cut_region(mesh, report.changed_tets);
    SCOPED_TRACE("cut " + std::to_string(cut));
    collapses += s.collapses;
    EXPECT_GE(s.min_quality_after, s.min_quality_before);
    EXPECT_GT(testing::min_volume(mesh.rest, mesh.tets), 0);
    EXPECT_GT(testing::min_volume(mesh.x, mesh.tets), 0);
    EXPECT_NEAR(total_volume(mesh.rest, mesh.tets), volume, 1e-9 * volume);
    EXPECT_EQ(testing::boundary_problem(mesh.tets), "");
    int parts = 0;
    testing::tet_components(mesh.tets, &parts);
    EXPECT_EQ(parts, 2);
    // Every boundary node on the box or on the cut plane (the snapped ones within snap times the
    // longest edge, as after the cut).
    const Triangles faces = boundary_faces(mesh.tets);
    std::vector<char> on_plane(static_cast<std::size_t>(mesh.num_nodes()), 0);
    for (Eigen::Index f = 0; f < faces.rows(); ++f) {
      for (int c = 0; c < 3; ++c) {
        const Vec3 p = row3(mesh.rest, faces(f, c));
        const bool on_box =
            (p.array().abs() < 1e-12).any() || ((p.array() - 1).abs() < 1e-12).any();
        const Real off = std::abs(n.dot(p - point));
        EXPECT_TRUE(on_box || off < 0.05 * 0.6) << "boundary node " << faces(f, c);
        on_plane[static_cast<std::size_t>(faces(f, c))] = !on_box && off < 0.05 * 0.6;
      }
    }
    // The bound on the cut region: tets with a node on the crack.
    for (int t = 0; t < mesh.num_tets(); ++t) {
      bool near = false;
      for (int k = 0; k < 4; ++k)
        near = near || on_plane[static_cast<std::size_t>(mesh.tets(t, k))];
      if (!near) continue;
      EXPECT_GE(tet_quality(row3(mesh.rest, mesh.tets(t, 0)), row3(mesh.rest, mesh.tets(t, 1)),
                            row3(mesh.rest, mesh.tets(t, 2)), row3(mesh.rest, mesh.tets(t, 3))),
                kQualityBound)
          << "tet " << t;
    }
  }
  EXPECT_GT(collapses, 0);
}

}  // namespace
}  // namespace incise::sim::cut
