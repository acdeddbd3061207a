#include "sim/render/primitives.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace incise::render {
namespace {

Eigen::Vector3d position(const ShapeMesh& mesh, std::uint32_t v) {
  const float* p = &mesh.vertices[v * ShapeMesh::floats_per_vertex];
  return Eigen::Vector3d(p[0], p[1], p[2]);
}

Eigen::Vector3d normal(const ShapeMesh& mesh, std::uint32_t v) {
  const float* p = &mesh.vertices[v * ShapeMesh::floats_per_vertex + 3];
  return Eigen::Vector3d(p[0], p[1], p[2]);
}

// Divergence theorem: the sum of signed tet volumes from the origin to each triangle is the
// enclosed volume when the surface is closed and wound counter-clockwise from outside
// (negative if wound the other way).
double enclosed_volume(const ShapeMesh& mesh) {
  double volume = 0.0;
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const Eigen::Vector3d a = position(mesh, mesh.indices[i]);
    const Eigen::Vector3d b = position(mesh, mesh.indices[i + 1]);
    const Eigen::Vector3d c = position(mesh, mesh.indices[i + 2]);
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

// Every triangle's winding normal agrees with its vertices' normals and none is degenerate.
void expect_consistent_winding(const ShapeMesh& mesh) {
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const Eigen::Vector3d a = position(mesh, mesh.indices[i]);
    const Eigen::Vector3d b = position(mesh, mesh.indices[i + 1]);
    const Eigen::Vector3d c = position(mesh, mesh.indices[i + 2]);
    const Eigen::Vector3d face = (b - a).cross(c - a);
    ASSERT_GT(face.norm(), 1e-9) << "triangle " << i / 3 << " is degenerate";
    for (int k = 0; k < 3; ++k) {
      ASSERT_GT(face.dot(normal(mesh, mesh.indices[i + k])), 0.0) << "triangle " << i / 3;
    }
  }
}

TEST(Primitives, SphereVerticesLieOnTheUnitSphereWithRadialNormals) {
  const ShapeMesh sphere = unit_sphere(12, 7);
  EXPECT_EQ(sphere.vertex_count(), 13 * 8);
  EXPECT_EQ(sphere.triangle_count(), 2 * 12 * 6);
  for (int v = 0; v < sphere.vertex_count(); ++v) {
    EXPECT_NEAR(position(sphere, v).norm(), 1.0, 1e-6);
    EXPECT_TRUE(normal(sphere, v).isApprox(position(sphere, v), 1e-6));
  }
  for (const std::uint32_t index : sphere.indices)
    ASSERT_LT(index, static_cast<std::uint32_t>(sphere.vertex_count()));
  expect_consistent_winding(sphere);
}

// An inscribed polyhedron encloses less than the sphere and converges to 4 pi / 3 under
// refinement; a positive volume also says the winding faces out.
TEST(Primitives, SphereVolumeApproachesTheBallsFromBelow) {
  const double ball = 4.0 * std::numbers::pi / 3.0;
  const double coarse = enclosed_volume(unit_sphere(8, 4));
  const double fine = enclosed_volume(unit_sphere(64, 32));
  EXPECT_GT(coarse, 0.0);
  EXPECT_LT(coarse, fine);
  EXPECT_LT(fine, ball);
  EXPECT_NEAR(fine, ball, 0.01 * ball);
}

TEST(Primitives, CylinderEnclosesTheInscribedPrism) {
  for (const int slices : {3, 7, 24}) {
    const ShapeMesh cylinder = unit_cylinder(slices);
    EXPECT_EQ(cylinder.triangle_count(), 4 * slices);
    const double prism = slices / 2.0 * std::sin(2.0 * std::numbers::pi / slices);
    EXPECT_NEAR(enclosed_volume(cylinder), prism, 1e-6) << slices << " slices";
    expect_consistent_winding(cylinder);
    for (int v = 0; v < cylinder.vertex_count(); ++v) {
      const Eigen::Vector3d p = position(cylinder, v);
      EXPECT_GE(p.z(), 0.0);
      EXPECT_LE(p.z(), 1.0);
      EXPECT_NEAR(normal(cylinder, v).norm(), 1.0, 1e-6);
    }
  }
}

TEST(Primitives, SquareSpansMinusOneToOneFacingUp) {
  const ShapeMesh square = unit_square();
  EXPECT_EQ(square.triangle_count(), 2);
  double area = 0.0;
  for (std::size_t i = 0; i < square.indices.size(); i += 3) {
    const Eigen::Vector3d a = position(square, square.indices[i]);
    const Eigen::Vector3d b = position(square, square.indices[i + 1]);
    const Eigen::Vector3d c = position(square, square.indices[i + 2]);
    area += 0.5 * (b - a).cross(c - a).z();
  }
  EXPECT_DOUBLE_EQ(area, 4.0);
  expect_consistent_winding(square);
}

TEST(Primitives, BoxIsTheCubeOfSideTwoWithFlatOutwardFaces) {
  const ShapeMesh box = unit_box();
  EXPECT_EQ(box.triangle_count(), 12);
  EXPECT_NEAR(enclosed_volume(box), 8.0, 1e-6);
  expect_consistent_winding(box);
  for (int v = 0; v < box.vertex_count(); ++v) {
    const Eigen::Vector3d p = position(box, v);
    const Eigen::Vector3d n = normal(box, v);
    EXPECT_DOUBLE_EQ(p.cwiseAbs().maxCoeff(), 1.0);
    // A face normal: one axis, and the vertex lies on that face.
    EXPECT_DOUBLE_EQ(n.cwiseAbs().sum(), 1.0);
    EXPECT_DOUBLE_EQ(n.dot(p), 1.0);
  }
}

TEST(Primitives, RejectsTooFewSegments) {
  EXPECT_THROW(unit_sphere(2, 4), std::invalid_argument);
  EXPECT_THROW(unit_sphere(8, 1), std::invalid_argument);
  EXPECT_THROW(unit_cylinder(2), std::invalid_argument);
}

}  // namespace
}  // namespace incise::render
