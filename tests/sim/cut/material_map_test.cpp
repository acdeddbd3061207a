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

}  // namespace
}  // namespace incise::sim::cut
