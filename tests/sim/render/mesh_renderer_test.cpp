#include "sim/render/mesh_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "gl_test.h"

namespace incise::render {
namespace {

using Pixel = std::array<int, 3>;

Pixel pixel(const std::vector<std::uint8_t>& rgb, int width, int row, int column) {
  const std::size_t i = (static_cast<std::size_t>(row) * width + column) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

// The shading formula documented on Shading, as 8-bit values before rounding.
Eigen::Vector3d expected_colour(const Shading& shading, const Eigen::Vector3d& normal) {
  const double lambert = std::max(0.0, normal.normalized().dot(shading.to_light.normalized()));
  const Eigen::Vector3d lit =
      shading.albedo.cast<double>() * (shading.ambient + shading.diffuse * lambert);
  return 255.0 * lit.cwiseMax(0.0).cwiseMin(1.0);
}

// One 8-bit step covers rounding either way when the shader's float result is converted.
void expect_colour(const Pixel& actual, const Eigen::Vector3d& expected) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(actual[c], expected[c], 1.0) << "channel " << c;
}

// Axis-aligned rectangle in the plane z, normal n for all four corners.
void rectangle(double x0, double x1, double y0, double y1, double z, const Eigen::Vector3d& n,
               Eigen::MatrixXd& V, Eigen::MatrixXd& N, Eigen::MatrixXi& F) {
  const Eigen::Index base = V.rows();
  V.conservativeResize(base + 4, 3);
  N.conservativeResize(base + 4, 3);
  F.conservativeResize(F.rows() + 2, 3);
  V.bottomRows(4) << x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z;
  N.bottomRows(4) = n.transpose().replicate(4, 1);
  F.bottomRows(2) << base, base + 1, base + 2, base, base + 2, base + 3;
}

Camera front_camera() {
  Camera camera;
  camera.eye = Eigen::Vector3d(0, 0, 2);
  camera.fov_y_deg = 60.0;
  return camera;
}

Shading test_shading() {
  Shading shading;
  shading.albedo = Eigen::Vector3f(0.6f, 0.4f, 0.9f);
  shading.ambient = 0.2f;
  shading.diffuse = 0.7f;
  shading.background = Eigen::Vector3f(10.0f, 20.0f, 30.0f) / 255.0f;
  return shading;
}

const Pixel background_pixel = {10, 20, 30};

using MeshRendererTest = GlTest;

TEST_F(MeshRendererTest, QuadFacingCameraIsLitAtCentreWithBackgroundAtCorner) {
  Eigen::MatrixXd V(0, 3), N(0, 3);
  Eigen::MatrixXi F(0, 3);
  rectangle(-0.5, 0.5, -0.5, 0.5, 0.0, Eigen::Vector3d::UnitZ(), V, N, F);
  Shading shading = test_shading();
  shading.to_light = Eigen::Vector3d(0.0, std::sin(std::numbers::pi / 3),
                                     std::cos(std::numbers::pi / 3));  // 60 deg

  MeshRenderer renderer;
  renderer.set_mesh(V, N, F);
  const Framebuffer target(64, 48);
  renderer.render(target, front_camera(), shading);
  const std::vector<std::uint8_t> rgb = target.read_rgb();

  expect_colour(pixel(rgb, 64, 24, 32), expected_colour(shading, Eigen::Vector3d::UnitZ()));
  EXPECT_EQ(pixel(rgb, 64, 0, 0), background_pixel);
  EXPECT_EQ(pixel(rgb, 64, 47, 63), background_pixel);
}

TEST_F(MeshRendererTest, FacingAwayFromLightIsDarkerAndOnlyAmbient) {
  Eigen::MatrixXd V(0, 3), N(0, 3);
  Eigen::MatrixXi F(0, 3);
  rectangle(-0.5, 0.5, -0.5, 0.5, 0.0, Eigen::Vector3d::UnitZ(), V, N, F);
  MeshRenderer renderer;
  renderer.set_mesh(V, N, F);
  const Framebuffer target(32, 32);

  Shading facing = test_shading();
  facing.to_light = Eigen::Vector3d::UnitZ();
  renderer.render(target, front_camera(), facing);
  const Pixel lit = pixel(target.read_rgb(), 32, 16, 16);

  Shading away = facing;
  away.to_light = -Eigen::Vector3d::UnitZ();
  renderer.render(target, front_camera(), away);
  const Pixel dark = pixel(target.read_rgb(), 32, 16, 16);

  expect_colour(lit, expected_colour(facing, Eigen::Vector3d::UnitZ()));
  expect_colour(dark, 255.0 * away.ambient * away.albedo.cast<double>());
  for (int c = 0; c < 3; ++c)
    EXPECT_LT(dark[c], lit[c]);
}

// A rectangle filling the world's upper-right quadrant must fill the image's upper-right
// quadrant: checks the camera's up and right and the readback's row order together.
TEST_F(MeshRendererTest, UpperRightOfWorldIsUpperRightOfImage) {
  Eigen::MatrixXd V(0, 3), N(0, 3);
  Eigen::MatrixXi F(0, 3);
  rectangle(0.0, 5.0, 0.0, 5.0, 0.0, Eigen::Vector3d::UnitZ(), V, N, F);
  MeshRenderer renderer;
  renderer.set_mesh(V, N, F);
  const int width = 64;
  const int height = 48;
  const Framebuffer target(width, height);
  const Shading shading = test_shading();
  renderer.render(target, front_camera(), shading);
  const std::vector<std::uint8_t> rgb = target.read_rgb();

  for (int row = 0; row < height; ++row) {
    for (int column = 0; column < width; ++column) {
      const bool covered = row < height / 2 && column >= width / 2;
      const Pixel actual = pixel(rgb, width, row, column);
      ASSERT_EQ(actual != background_pixel, covered) << "row " << row << " column " << column;
    }
  }
}

// The nearer surface wins even when it is drawn first.
TEST_F(MeshRendererTest, DepthTestKeepsTheNearerSurface) {
  Eigen::MatrixXd V(0, 3), N(0, 3);
  Eigen::MatrixXi F(0, 3);
  rectangle(-0.5, 0.5, -0.5, 0.5, 0.5, Eigen::Vector3d::UnitZ(), V, N, F);   // near, lit
  rectangle(-1.0, 1.0, -1.0, 1.0, 0.0, -Eigen::Vector3d::UnitZ(), V, N, F);  // far, unlit
  MeshRenderer renderer;
  renderer.set_mesh(V, N, F);
  const Framebuffer target(32, 32);
  Shading shading = test_shading();
  shading.to_light = Eigen::Vector3d::UnitZ();
  renderer.render(target, front_camera(), shading);
  expect_colour(pixel(target.read_rgb(), 32, 16, 16),
                expected_colour(shading, Eigen::Vector3d::UnitZ()));
}

TEST_F(MeshRendererTest, EmptyMeshRendersBackgroundOnly) {
  MeshRenderer renderer;
  const Framebuffer target(8, 8);
  renderer.render(target, front_camera(), test_shading());
  EXPECT_EQ(pixel(target.read_rgb(), 8, 4, 4), background_pixel);
}

TEST_F(MeshRendererTest, RejectsInconsistentMeshes) {
  MeshRenderer renderer;
  Eigen::MatrixXd V(0, 3), N(0, 3);
  Eigen::MatrixXi F(0, 3);
  rectangle(-0.5, 0.5, -0.5, 0.5, 0.0, Eigen::Vector3d::UnitZ(), V, N, F);
  EXPECT_THROW(renderer.set_mesh(V, N.topRows(3), F), std::invalid_argument);
  EXPECT_THROW(renderer.set_mesh(V, N, F.leftCols(2)), std::invalid_argument);
  Eigen::MatrixXi out_of_range = F;
  out_of_range(1, 2) = 4;
  EXPECT_THROW(renderer.set_mesh(V, N, out_of_range), std::invalid_argument);
  out_of_range(1, 2) = -1;
  EXPECT_THROW(renderer.set_mesh(V, N, out_of_range), std::invalid_argument);
}

}  // namespace
}  // namespace incise::render
