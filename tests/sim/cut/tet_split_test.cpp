// The cases of one cut tet (sim/cut/tet_split.h): the classification of crossing patterns, and a
// single tet cut by a plane in each case into the expected pieces, with the pieces' volumes
// against the closed-form volumes of the two parts of the tet.

#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "cut_checks.h"
#include "sim/cut/cut_mesh.h"
#include "sim/cut/tet_split.h"

namespace incise::sim::cut {
namespace {

using testing::plane_blade;
using testing::tet_components;

// The corner tet (0, e_x, e_y, e_z), volume 1/6.
TetMesh corner_tet() {
  Points rest(4, 3);
  rest << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Tets tets(1, 4);
  tets << 0, 1, 2, 3;
  TetMesh mesh = make_tet_mesh(rest, tets);
  mesh.labels.setConstant(3);
  return mesh;
}

Real tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return std::abs(signed_volume(a, b, c, d));
}

// Volumes of the components of mesh, the one holding `node` first.
std::array<Real, 2> component_volumes(const TetMesh& mesh, int node) {
  int count = 0;
  const std::vector<int> component = tet_components(mesh.tets, &count);
  EXPECT_EQ(count, 2);
  int first = -1;
  std::array<Real, 2> volume{};
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      if (mesh.tets(t, k) == node) first = component[static_cast<std::size_t>(t)];
    }
  }
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Real v =
        signed_volume(row3(mesh.rest, mesh.tets(t, 0)), row3(mesh.rest, mesh.tets(t, 1)),
                      row3(mesh.rest, mesh.tets(t, 2)), row3(mesh.rest, mesh.tets(t, 3)));
    volume[component[static_cast<std::size_t>(t)] == first ? 0 : 1] += v;
  }
  return volume;
}

struct CaseExpectation {
  TetCutCase kind;
  int tets;
  int new_nodes;  // crossings, then crack copies
};

void cut_and_check(const Vec3& point, const Vec3& normal, const CaseExpectation& expected,
                   int first_side_node, Real first_side_volume) {
  const TetMesh before = corner_tet();
  TetMesh mesh = before;
  const CutSurface blade = plane_blade(point, normal, 3);
  const CutReport report = cut_mesh(mesh, blade);
  EXPECT_EQ(report.cases[static_cast<std::size_t>(expected.kind)], 1);
  EXPECT_EQ(mesh.num_tets(), expected.tets);
  EXPECT_EQ(static_cast<int>(report.new_nodes.size()), expected.new_nodes);
  testing::expect_cut_invariants(before, mesh, report, blade, CutOptions{}.snap);
  const std::array<Real, 2> volume = component_volumes(mesh, first_side_node);
  EXPECT_NEAR(volume[0], first_side_volume, 1e-14);
  EXPECT_NEAR(volume[1], 1.0 / 6 - first_side_volume, 1e-14);
}

TEST(ClassifyTetCut, PatternsOfCompleteAndPartialCuts) {
  const std::array<bool, 4> off = {false, false, false, false};
  // Edges (0,1) (0,2) (0,3): vertex 0 alone, the tip case.
  TetCutPattern tip = classify_tet_cut({true, true, true, false, false, false}, off);
  EXPECT_EQ(tip.kind, TetCutCase::tip);
  EXPECT_EQ(tip.side, (std::array<int, 4>{0, 1, 1, 1}));
  // All but (0,1) and (2,3): {0, 1} against {2, 3}.
  TetCutPattern split = classify_tet_cut({false, true, true, true, true, false}, off);
  EXPECT_EQ(split.kind, TetCutCase::split);
  EXPECT_EQ(split.side, (std::array<int, 4>{0, 0, 1, 1}));
  // Partial cuts: one edge, two edges, three edges of a face, five, six.
  EXPECT_EQ(classify_tet_cut({true, false, false, false, false, false}, off).kind,
            TetCutCase::none);
  EXPECT_EQ(classify_tet_cut({true, true, false, false, false, false}, off).kind, TetCutCase::none);
  EXPECT_EQ(classify_tet_cut({true, true, false, true, false, false}, off).kind, TetCutCase::none);
  EXPECT_EQ(classify_tet_cut({true, true, true, true, true, false}, off).kind, TetCutCase::none);
  EXPECT_EQ(classify_tet_cut({true, true, true, true, true, true}, off).kind, TetCutCase::none);
  // Vertex 3 on the surface, edges (0,1) (1,2) cut: vertex 1 against {0, 2}.
  TetCutPattern vertex =
      classify_tet_cut({true, false, false, true, false, false}, {false, false, false, true});
  EXPECT_EQ(vertex.kind, TetCutCase::through_vertex);
  EXPECT_EQ(vertex.side, (std::array<int, 4>{0, 1, 0, -1}));
  // Vertices 2, 3 on the surface, edge (0,1) cut.
  EXPECT_EQ(
      classify_tet_cut({true, false, false, false, false, false}, {false, false, true, true}).kind,
      TetCutCase::through_edge);
  // Three vertices on the surface: no subdivision (the face case of cut_mesh).
  EXPECT_EQ(
      classify_tet_cut({false, false, false, false, false, false}, {false, true, true, true}).kind,
      TetCutCase::none);
}

TEST(BisectTet, SplitsInOrderAndKeepsOrientation) {
  std::vector<std::array<int, 4>> pieces;
  const std::vector<EdgeSplit> splits = {{0, 2, 10}, {0, 3, 11}, {1, 2, 12}, {1, 3, 13}};
  bisect_tet({0, 1, 2, 3}, splits, pieces);
  ASSERT_EQ(pieces.size(), 6u);
  // Positions: the corner tet and the middles of the split edges.
  Points p(14, 3);
  p.setZero();
  p.row(1) << 1, 0, 0;
  p.row(2) << 0, 1, 0;
  p.row(3) << 0, 0, 1;
  for (const EdgeSplit& s : splits)
    p.row(s.middle) = (p.row(s.a) + p.row(s.b)) / 2;
  Real volume = 0;
  for (const auto& t : pieces) {
    const Real v = signed_volume(row3(p, t[0]), row3(p, t[1]), row3(p, t[2]), row3(p, t[3]));
    EXPECT_GT(v, 0);
    volume += v;
  }
  EXPECT_NEAR(volume, 1.0 / 6, 1e-15);
  // A split that is not an edge of the tet leaves it alone.
  pieces.clear();
  const std::vector<EdgeSplit> other = {{5, 6, 7}};
  bisect_tet({0, 1, 2, 3}, other, pieces);
  EXPECT_EQ(pieces.size(), 1u);
}

TEST(CutTet, TipCaseSeparatesTheCornerIntoFourTets) {
  // x = 0.4 cuts off vertex 1: a tip of side 0.6.
  cut_and_check({0.4, 0, 0}, {1, 0, 0}, {TetCutCase::tip, 4, 6}, 1, std::pow(0.6, 3) / 6);
}

TEST(CutTet, SplitCaseGivesTwoPrismsOfThreeTets) {
  // x + y = 0.6 separates {1, 2} from {0, 3}; the part x + y >= c of the corner tet has volume
  // int_c^1 s (1 - s) ds = 1/6 - c^2 / 2 + c^3 / 3.
  const Real c = 0.6;
  cut_and_check({c, 0, 0}, {1, 1, 0}, {TetCutCase::split, 6, 8}, 1,
                1.0 / 6 - c * c / 2 + c * c * c / 3);
}

TEST(CutTet, ThroughVertexCaseGivesThreeTets) {
  // x + z / 2 = 1/2 passes through vertex 3 and the middles of edges (0,1) and (1,2); vertex 1's
  // side is the tet (e_x, m01, m12, e_z). Vertex 3 is duplicated with the crossings.
  const Real tip = tet_volume({1, 0, 0}, {0.5, 0, 0}, {0.5, 0.5, 0}, {0, 0, 1});
  cut_and_check({0.5, 0, 0}, {1, 0, 0.5}, {TetCutCase::through_vertex, 3, 5}, 1, tip);
}

TEST(CutTet, ThroughEdgeCaseGivesTwoTets) {
  // 2x + y + z = 1 holds edge (2,3) and the middle of edge (0,1): two halves of 1/12.
  cut_and_check({0.5, 0, 0}, {2, 1, 1}, {TetCutCase::through_edge, 2, 4}, 1, 1.0 / 12);
}

TEST(CutTet, FaceOnTheSurfaceOpensWithoutSubdivision) {
  // Two tets on either side of the face (e_x, e_y, e_z); the blade lies in that face's plane.
  Points rest(5, 3);
  rest << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  Tets tets(2, 4);
  tets << 0, 1, 2, 3, 4, 1, 3, 2;
  const TetMesh before = make_tet_mesh(rest, tets);
  ASSERT_GT(testing::min_volume(before.rest, before.tets), 0);
  TetMesh mesh = before;
  const CutSurface blade = plane_blade({1.0 / 3, 1.0 / 3, 1.0 / 3}, {1, 1, 1}, 3);
  const CutReport report = cut_mesh(mesh, blade);
  EXPECT_EQ(report.faces_opened, 1);
  EXPECT_EQ(report.snapped_nodes, 3);
  EXPECT_EQ(mesh.num_tets(), 2);
  EXPECT_EQ(mesh.num_nodes(), 8);  // the face's 3 nodes, once more
  testing::expect_cut_invariants(before, mesh, report, blade, CutOptions{}.snap);
  const std::array<Real, 2> volume = component_volumes(mesh, 0);
  EXPECT_NEAR(volume[0], 1.0 / 6, 1e-15);
}

TEST(CutTet, BladeStoppingInsideLeavesTheTetWhole) {
  // The blade covers only part of the plane x = 0.4: edge (0,1) is crossed, (1,2) and (1,3) are
  // not, a partial cut (not done: no temporary subdivision), so nothing changes.
  const TetMesh before = corner_tet();
  TetMesh mesh = before;
  const CutSurface blade =
      blade_sweep({0.4, -1, -0.1}, {0.4, 0.1, -0.1}, {0.4, -1, 0.1}, {0.4, 0.1, 0.1});
  const CutReport report = cut_mesh(mesh, blade);
  EXPECT_EQ(mesh.num_tets(), 1);
  EXPECT_EQ(mesh.num_nodes(), 4);
  EXPECT_TRUE(report.changed_tets.empty());
  EXPECT_EQ(mesh.tets, before.tets);
}

TEST(CutMesh, RejectsBadInput) {
  TetMesh mesh = corner_tet();
  const CutSurface blade = plane_blade({0.4, 0, 0}, {1, 0, 0}, 3);
  EXPECT_THROW(cut_mesh(mesh, blade, CutOptions{0.5}), std::invalid_argument);
  EXPECT_THROW(cut_mesh(mesh, blade, CutOptions{0}), std::invalid_argument);
  mesh.v.resize(2, 3);
  EXPECT_THROW(cut_mesh(mesh, blade), std::invalid_argument);
  EXPECT_EQ(mesh.num_tets(), 1);
  EXPECT_THROW(blade_sweep({0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::cut
