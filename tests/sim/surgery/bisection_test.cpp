// Local refinement by edge bisection and its undo (sim/surgery/bisection.h) on a box mesh: the
// refined mesh is conforming with the same volume and boundary, every edge near the centre is
// short enough, the new nodes carry an affine state exactly with momentum and centre of mass
// kept, and undoing restores the original tets exactly.

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "sim/cut/simplify_cut.h"
#include "sim/mesh/box_mesher.h"
#include "sim/surgery/bisection.h"

namespace incise::sim::surgery {
namespace {

const Vec3 kSize(0.06, 0.06, 0.03);

TetMesh box() {
  return make_box_mesh(kSize, Vec3i(6, 6, 3));
}

using Face = std::array<int, 3>;

// Every face held by one tet lies on the box's boundary, none is held by three: no hanging node.
void expect_conforming(const TetMesh& mesh) {
  std::map<Face, int> faces;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int skip = 0; skip < 4; ++skip) {
      Face f{};
      int k = 0;
      for (int j = 0; j < 4; ++j) {
        if (j != skip) f[static_cast<std::size_t>(k++)] = mesh.tets(t, j);
      }
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  }
  int inner_boundary = 0;
  for (const auto& [f, count] : faces) {
    ASSERT_LE(count, 2);
    if (count == 2) continue;
    const Vec3 c = (row3(mesh.rest, f[0]) + row3(mesh.rest, f[1]) + row3(mesh.rest, f[2])) / 3;
    bool on_side = false;
    for (int axis = 0; axis < 3; ++axis) {
      on_side = on_side || std::abs(c(axis)) < 1e-12 || std::abs(c(axis) - kSize(axis)) < 1e-12;
    }
    if (!on_side) ++inner_boundary;
  }
  EXPECT_EQ(inner_boundary, 0);
}

Real min_volume(const TetMesh& mesh) {
  return tet_volumes(mesh.rest, mesh.tets).minCoeff();
}

// Lumped masses V/4 per node and tet (unit density).
VecX lumped(const TetMesh& mesh) {
  VecX m = VecX::Zero(mesh.num_nodes());
  const VecX v = tet_volumes(mesh.rest, mesh.tets);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k)
      m(mesh.tets(t, k)) += v(t) / 4;
  }
  return m;
}

Vec3 weighted_sum(const VecX& m, const Points& p) {
  return (p.transpose() * m);
}

TEST(Bisection, RefinementIsConformingKeepsTheVolumeAndShortensEveryEdgeNearTheCentre) {
  TetMesh mesh = box();
  const Real volume = total_volume(mesh.rest, mesh.tets);
  const int tets = mesh.num_tets();
  const Vec3 centre(0.03, 0.03, 0.03);  // on the top face
  BisectionSettings settings;
  settings.edge_length = 0.004;
  const BisectionReport report = refine_ball(mesh, centre, 0.012, settings);
  EXPECT_GT(report.splits, 20);
  EXPECT_EQ(report.refused, 0);
  EXPECT_EQ(mesh.num_nodes(), report.nodes_before + report.splits);
  EXPECT_NEAR(total_volume(mesh.rest, mesh.tets), volume, 1e-12 * volume);
  EXPECT_GT(min_volume(mesh), 0);
  expect_conforming(mesh);
  Real worst = 1;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    std::array<Vec3, 4> p;
    for (int k = 0; k < 4; ++k)
      p[static_cast<std::size_t>(k)] = row3(mesh.rest, mesh.tets(t, k));
    worst = std::min(worst, cut::tet_quality(p[0], p[1], p[2], p[3]));
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        const Vec3 a = p[static_cast<std::size_t>(i)], b = p[static_cast<std::size_t>(j)];
        const Real s = std::clamp((centre - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        if ((a + s * (b - a) - centre).norm() <= 0.012) {
          EXPECT_LE((b - a).norm(), 0.004 + 1e-15);
        }
      }
    }
  }
  EXPECT_GE(worst, settings.min_quality);
  // The report: a changed slot per replaced and appended tet, each with an old parent.
  EXPECT_EQ(
      static_cast<int>(report.changed.size()), mesh.num_tets() - tets + [&] {
        int replaced = 0;
        for (const int s : report.changed)
          replaced += s < tets ? 1 : 0;
        return replaced;
      }());
  for (std::size_t k = 0; k < report.changed.size(); ++k) {
    ASSERT_GE(report.parents[k], 0);
    ASSERT_LT(report.parents[k], tets);
  }
}

TEST(Bisection, NewNodesCarryAnAffineStateAndKeepMomentumAndCentreOfMass) {
  TetMesh mesh = box();
  Mat3 a;
  a << 1.1, 0.2, -0.05, 0.03, 0.9, 0.1, -0.2, 0.05, 1.3;
  const Vec3 shift(0.01, -0.02, 0.005);
  Mat3 b;
  b << 0.5, -1, 2, 0.1, 0.3, -0.7, 1.5, 0.2, 0.1;
  mesh.x = (mesh.rest * a.transpose()).rowwise() + shift.transpose();
  mesh.v = mesh.rest * b.transpose();
  mesh.v.col(0).array() += 0.3;
  const VecX m0 = lumped(mesh);
  const Vec3 momentum = weighted_sum(m0, mesh.v), moment = weighted_sum(m0, mesh.x);
  const BisectionReport report = refine_ball(mesh, Vec3(0.01, 0.02, 0.0), 0.015, {});
  ASSERT_GT(report.splits, 0);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Vec3 r = row3(mesh.rest, i);
    Vec3 v = b * r;
    v.x() += 0.3;
    EXPECT_LT((row3(mesh.x, i) - (a * r + shift)).norm(), 1e-15);
    EXPECT_LT((row3(mesh.v, i) - v).norm(), 1e-14);
  }
  const VecX m1 = lumped(mesh);
  EXPECT_NEAR(m1.sum(), m0.sum(), 1e-12 * m0.sum());
  EXPECT_LT((weighted_sum(m1, mesh.v) - momentum).norm(), 1e-12 * momentum.norm());
  EXPECT_LT((weighted_sum(m1, mesh.x) - moment).norm(), 1e-12 * moment.norm());
}

TEST(Bisection, UndoingEverySplitRestoresTheOriginalTetsExactly) {
  const TetMesh original = box();
  TetMesh mesh = original;
  std::vector<Bisection> splits = refine_ball(mesh, Vec3(0.03, 0.03, 0.03), 0.012, {}).bisections;
  const std::vector<Bisection> second =
      refine_ball(mesh, Vec3(0.0, 0.06, 0.015), 0.01, {}).bisections;
  splits.insert(splits.end(), second.begin(), second.end());
  ASSERT_GT(second.size(), 0u);
  const CoarsenReport report = undo_bisections(mesh, splits, {});
  EXPECT_EQ(report.undone, static_cast<int>(report.node_map.size()) - original.num_nodes());
  EXPECT_TRUE(splits.empty());
  ASSERT_EQ(mesh.num_nodes(), original.num_nodes());
  ASSERT_EQ(mesh.num_tets(), original.num_tets());
  EXPECT_EQ(mesh.rest, original.rest);
  // The same tets, with the same orientation (a tet keeps its node order up to the slot order).
  const auto sorted_rows = [](const Tets& tets) {
    std::vector<std::array<int, 4>> rows;
    for (int t = 0; t < tets.rows(); ++t)
      rows.push_back({tets(t, 0), tets(t, 1), tets(t, 2), tets(t, 3)});
    std::sort(rows.begin(), rows.end());
    return rows;
  };
  EXPECT_EQ(sorted_rows(mesh.tets), sorted_rows(original.tets));
}

TEST(Bisection, PartialUndoKeepsTheRegionAskedForAndStaysConforming) {
  TetMesh mesh = box();
  const Real volume = total_volume(mesh.rest, mesh.tets);
  const Vec3 kept(0.03, 0.03, 0.03), dropped(0.0, 0.06, 0.015);
  std::vector<Bisection> splits = refine_ball(mesh, kept, 0.012, {}).bisections;
  const std::vector<Bisection> more = refine_ball(mesh, dropped, 0.01, {}).bisections;
  splits.insert(splits.end(), more.begin(), more.end());
  const auto inside = [&](const Vec3& rest) { return (rest - kept).norm() < 0.02; };
  const auto count_inside = [&](const std::vector<Bisection>& list) {
    return std::count_if(list.begin(), list.end(),
                         [&](const Bisection& s) { return inside(row3(mesh.rest, s.mid)); });
  };
  const auto kept_before = count_inside(splits);
  const CoarsenReport report = undo_bisections(mesh, splits, inside);
  EXPECT_GT(report.undone, 0);
  EXPECT_EQ(count_inside(splits), kept_before);
  for (const Bisection& s : splits) {
    // Still the rest midpoint of its (renumbered) edge.
    EXPECT_LT((row3(mesh.rest, s.mid) - 0.5 * (row3(mesh.rest, s.a) + row3(mesh.rest, s.b))).norm(),
              1e-15);
  }
  // Those left outside the region are held by kept splits (on their propagation path): a second
  // pass undoes nothing more, and undoing the rest too restores the original mesh.
  EXPECT_EQ(undo_bisections(mesh, splits, inside).undone, 0);
  expect_conforming(mesh);
  EXPECT_GT(min_volume(mesh), 0);
  EXPECT_NEAR(total_volume(mesh.rest, mesh.tets), volume, 1e-12 * volume);
  undo_bisections(mesh, splits, {});
  EXPECT_TRUE(splits.empty());
  EXPECT_EQ(mesh.rest, box().rest);
}

TEST(Bisection, PartialUndoLeavesAConformingMesh) {
  TetMesh mesh = box();
  const Real volume = total_volume(mesh.rest, mesh.tets);
  std::vector<Bisection> splits = refine_ball(mesh, Vec3(0.03, 0.03, 0.03), 0.012, {}).bisections;
  undo_bisections(mesh, splits, [](const Vec3& rest) { return rest.x() < 0.03; });
  expect_conforming(mesh);
  EXPECT_GT(min_volume(mesh), 0);
  EXPECT_NEAR(total_volume(mesh.rest, mesh.tets), volume, 1e-12 * volume);
}

TEST(Bisection, TheAltitudeFloorAndFrozenTetsRefuseSplits) {
  TetMesh mesh = box();
  BisectionSettings settings;
  settings.edge_length = 0.002;
  settings.min_altitude = 0.004;  // 2 mm edges would need altitudes of about 1 mm
  const BisectionReport floor = refine_ball(mesh, Vec3(0.03, 0.03, 0.03), 0.01, settings);
  EXPECT_GT(floor.refused, 0);
  for (const int t : floor.changed) {
    const Vec3 a = row3(mesh.rest, mesh.tets(t, 0)), b = row3(mesh.rest, mesh.tets(t, 1)),
               c = row3(mesh.rest, mesh.tets(t, 2)), d = row3(mesh.rest, mesh.tets(t, 3));
    const Real face = 0.5 * std::max({(b - a).cross(c - a).norm(), (b - a).cross(d - a).norm(),
                                      (c - a).cross(d - a).norm(), (c - b).cross(d - b).norm()});
    EXPECT_GE(3 * signed_volume(a, b, c, d) / face, settings.min_altitude);
  }

  TetMesh frozen_mesh = box();
  const std::vector<char> frozen(static_cast<std::size_t>(frozen_mesh.num_tets()), 1);
  const BisectionReport none = refine_ball(frozen_mesh, Vec3(0.03, 0.03, 0.03), 0.01, {}, frozen);
  EXPECT_EQ(none.splits, 0);
  EXPECT_GT(none.refused, 0);
  EXPECT_EQ(frozen_mesh.tets, box().tets);
}

TEST(Bisection, BadSettingsAreRefused) {
  TetMesh mesh = box();
  BisectionSettings bad;
  bad.edge_length = 0;
  EXPECT_THROW(refine_ball(mesh, Vec3::Zero(), 0.01, bad), std::invalid_argument);
  EXPECT_THROW(refine_ball(mesh, Vec3::Zero(), -1, {}), std::invalid_argument);
  EXPECT_THROW(refine_ball(mesh, Vec3::Constant(NAN), 0.01, {}), std::invalid_argument);
  const std::vector<char> wrong(3, 0);
  EXPECT_THROW(refine_ball(mesh, Vec3::Zero(), 0.01, {}, wrong), std::invalid_argument);
  std::vector<Bisection> out_of_range{{mesh.num_nodes(), 0, 1}};
  EXPECT_THROW(undo_bisections(mesh, out_of_range, {}), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::surgery
