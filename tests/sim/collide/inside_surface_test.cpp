// inside_closed_surface (the ray's parity) against the closed form on a sheared box: p is inside
// exactly when the box's inverse map takes it into [0, size].
#include "sim/collide/inside_surface.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "sim/collide/mesh_surface_faces.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"

namespace incise::sim::collide {
namespace {

TEST(InsideClosedSurface, AgreesWithTheClosedFormOnAShearedBox) {
  const Vec3 size(0.04, 0.03, 0.02);
  TetMesh mesh = make_box_mesh(size, Vec3i(4, 3, 2));
  Mat3 map;
  map << 1.0, 0.3, -0.2, 0.1, 0.9, 0.25, -0.15, 0.05, 1.1;
  const Vec3 shift(0.01, -0.02, 0.005);
  for (int i = 0; i < mesh.num_nodes(); ++i)
    mesh.x.row(i) = (map * row3(mesh.rest, i) + shift).transpose();
  SurfaceBvh bvh;
  bvh.build(mesh.x, mesh_surface_faces(boundary_surface(mesh)));
  const Mat3 inverse = map.inverse();
  std::mt19937 random(5);
  std::uniform_real_distribution<Real> unit(-0.3, 1.3);
  std::vector<int> scratch;
  int inside = 0, outside = 0;
  for (int q = 0; q < 2000; ++q) {
    const Vec3 box_point(unit(random) * size.x(), unit(random) * size.y(), unit(random) * size.z());
    // Clear of the faces by 0.1 mm in the box's own frame (on a face the parity is a tie).
    const Vec3 to_faces = box_point.cwiseAbs().cwiseMin((size - box_point).cwiseAbs());
    if (to_faces.minCoeff() < 1e-4) continue;
    const Vec3 p = map * box_point + shift;
    const Vec3 back = inverse * (p - shift);
    const bool expected = (back.array() > 0).all() && (back.array() < size.array()).all();
    EXPECT_EQ(inside_closed_surface(bvh, mesh.x, p, scratch), expected) << p.transpose();
    (expected ? inside : outside) += 1;
  }
  EXPECT_GT(inside, 200);
  EXPECT_GT(outside, 200);
}

}  // namespace
}  // namespace incise::sim::collide
