// material_map_at (sim/cut/material_map.h): the current -> rest map of the tet at a point, checked
// against an affine deformation whose inverse is known, and its refusals.

#include <gtest/gtest.h>

#include <random>

#include "cut_checks.h"
#include "sim/cut/material_map.h"

namespace incise::sim::cut {
namespace {

TEST(MaterialMap, InvertsAnAffineDeformationInsideAndNearTheMesh) {
  TetMesh mesh = testing::jittered_box({1, 1, 1}, {3, 3, 3}, 0.2, 11);
  Mat3 a;
  a << 1.2, 0.3, 0, -0.1, 0.9, 0.2, 0.05, 0, 1.1;  // det > 0
  const Vec3 shift(0.4, -0.3, 2);
  for (int i = 0; i < mesh.num_nodes(); ++i)
    mesh.x.row(i) = (a * row3(mesh.rest, i) + shift).transpose();
  std::mt19937 random(3);
  std::uniform_real_distribution<Real> unit(0.01, 0.99);
  for (int k = 0; k < 50; ++k) {
    const Vec3 rest(unit(random), unit(random), unit(random));
    const auto map = material_map_at(mesh, a * rest + shift, 0.5);
    ASSERT_TRUE(map);
    EXPECT_TRUE(map->inside);
    EXPECT_LT((map->rest_of(a * rest + shift) - rest).norm(), 1e-12);
    // The tet's map is the whole mesh's here, so it holds for far points too (a blade's end).
    EXPECT_LT((map->rest_of(a * Vec3(3, -1, 2) + shift) - Vec3(3, -1, 2)).norm(), 1e-12);
  }
  // Just outside: the nearest tet's map, flagged as not inside.
  const Vec3 outside(1.1, 0.5, 0.5);
  const auto near = material_map_at(mesh, a * outside + shift, 0.5);
  ASSERT_TRUE(near);
  EXPECT_FALSE(near->inside);
  EXPECT_LT((near->rest_of(a * outside + shift) - outside).norm(), 1e-12);
  // Out of reach: nothing.
  EXPECT_FALSE(material_map_at(mesh, a * Vec3(5, 5, 5) + shift, 0.5));
}

TEST(MaterialMap, RefusesASquashedOrInvertedTet) {
  TetMesh mesh = testing::jittered_box({1, 1, 1}, {1, 1, 1}, 0, 1);
  const Vec3 p(0.2, 0.3, 0.25);
  const auto map = material_map_at(mesh, p, 0.5);
  ASSERT_TRUE(map);
  const int t = map->tet;
  // Flatten that tet: move its last node onto the plane of the other three.
  const Vec3 o = row3(mesh.x, mesh.tets(t, 0));
  const Vec3 n = (row3(mesh.x, mesh.tets(t, 1)) - o).cross(row3(mesh.x, mesh.tets(t, 2)) - o);
  const int d = mesh.tets(t, 3);
  const Vec3 flat = row3(mesh.x, d) - n.normalized().dot(row3(mesh.x, d) - o) * n.normalized();
  TetMesh squashed = mesh;
  squashed.x.row(d) = flat.transpose();
  const auto refused = material_map_at(squashed, p, 0.5);
  EXPECT_TRUE(!refused || refused->tet != t) << "a flat tet's map means nothing";
  // Mirrored through that plane: inverted.
  TetMesh inverted = mesh;
  inverted.x.row(d) = (2 * flat - row3(mesh.x, d)).transpose();
  const auto mirrored = material_map_at(inverted, p, 0.5);
  EXPECT_TRUE(!mirrored || mirrored->tet != t);
}

// tangled_near: a tet of a 3 x 3 x 3 box turned inside out (a node mirrored through its opposite
// face; the tets around that node may turn with it) is found by a blade meeting the inverted tets'
// boxes grown by reach, and by no blade passing beyond.
TEST(MaterialMap, FindsInvertedTetsNearTheBladeOnly) {
  const TetMesh mesh = testing::jittered_box({3, 3, 3}, {3, 3, 3}, 0.1, 5);
  const Real reach = 0.25;
  // Unchanged, nothing is tangled anywhere.
  EXPECT_FALSE(tangled_near(mesh, Vec3(-1, 1.5, 1.5), Vec3(4, 1.5, 1.5), reach));
  // A tet of the corner cell at the origin, inverted.
  int t = 0;
  for (; t < mesh.num_tets(); ++t) {
    Vec3 centroid = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
      centroid += 0.25 * row3(mesh.rest, mesh.tets(t, k));
    if ((centroid.array() < 1).all()) break;
  }
  ASSERT_LT(t, mesh.num_tets());
  TetMesh tangled = mesh;
  const Vec3 o = row3(mesh.x, mesh.tets(t, 0));
  const Vec3 n = (row3(mesh.x, mesh.tets(t, 1)) - o).cross(row3(mesh.x, mesh.tets(t, 2)) - o);
  const int d = mesh.tets(t, 3);
  const Vec3 flat = row3(mesh.x, d) - n.normalized().dot(row3(mesh.x, d) - o) * n.normalized();
  tangled.x.row(d) = (2 * flat - row3(mesh.x, d)).transpose();
  // The box of every inverted tet (t among them).
  const auto volume = [](const Points& p, const Tets& tets, int s) {
    const Vec3 a = row3(p, tets(s, 0));
    Mat3 e;
    for (int k = 1; k < 4; ++k)
      e.col(k - 1) = row3(p, tets(s, k)) - a;
    return e.determinant();
  };
  Vec3 lo = Vec3::Constant(1e9), hi = Vec3::Constant(-1e9);
  int inverted = 0;
  for (int s = 0; s < tangled.num_tets(); ++s) {
    if (volume(tangled.x, tangled.tets, s) * volume(tangled.rest, tangled.tets, s) > 0) continue;
    ++inverted;
    for (int k = 0; k < 4; ++k) {
      lo = lo.cwiseMin(row3(tangled.x, tangled.tets(s, k)));
      hi = hi.cwiseMax(row3(tangled.x, tangled.tets(s, k)));
    }
  }
  ASSERT_GE(inverted, 1);
  ASSERT_LT(hi.maxCoeff() + reach, 2.5);  // clear of the far blade below
  // A blade through the boxes, one passing just within reach above them, one just beyond, one
  // diagonal that clips the corner of t's grown box between the edge's ends.
  const Vec3 mid = 0.5 * (lo + hi);
  EXPECT_TRUE(tangled_near(tangled, mid - Vec3(2, 0, 0), mid + Vec3(2, 0, 0), reach));
  EXPECT_TRUE(tangled_near(tangled, Vec3(-2, mid.y(), hi.z() + 0.9 * reach),
                           Vec3(2, mid.y(), hi.z() + 0.9 * reach), reach));
  EXPECT_FALSE(tangled_near(tangled, Vec3(-2, mid.y(), hi.z() + 1.1 * reach),
                            Vec3(2, mid.y(), hi.z() + 1.1 * reach), reach));
  Vec3 t_hi = row3(tangled.x, tangled.tets(t, 0));
  for (int k = 1; k < 4; ++k)
    t_hi = t_hi.cwiseMax(row3(tangled.x, tangled.tets(t, k)));
  const Vec3 corner = t_hi + Vec3::Constant(0.9 * reach);  // in t's grown box, off its own
  EXPECT_TRUE(tangled_near(tangled, corner + Vec3(1, -1, 0), corner + Vec3(-1, 1, 0), reach));
  // A blade far across the box; no reach at all.
  EXPECT_FALSE(tangled_near(tangled, Vec3(2.5, -1, 2.5), Vec3(2.5, 4, 2.5), reach));
  EXPECT_TRUE(tangled_near(tangled, mid - Vec3(2, 0, 0), mid + Vec3(2, 0, 0), -1));
}

}  // namespace
}  // namespace incise::sim::cut
