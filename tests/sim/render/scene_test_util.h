#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sim/render/camera.h"
#include "sim/render/scene_renderer.h"

namespace incise::render::test {

using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Pixel = std::array<int, 3>;

// A tissue surface owning its arrays; view() points at them.
struct Surface {
  Positions V;
  Positions N;
  Faces F;
  TissueView view() const { return {&V, &N, &F}; }
};

// The square [-half, half]^2 of the xy plane as an n by n grid of quads, rotated by rotation and
// moved to centre; normals are the rotated +z.
inline Surface square_surface(double half, int n, const Eigen::Matrix3d& rotation,
                              const Eigen::Vector3d& centre) {
  Surface s;
  s.V.resize((n + 1) * (n + 1), 3);
  s.N.resize((n + 1) * (n + 1), 3);
  s.F.resize(2 * n * n, 3);
  const Eigen::Vector3d normal = rotation * Eigen::Vector3d::UnitZ();
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const Eigen::Vector3d local(-half + 2 * half * i / n, -half + 2 * half * j / n, 0.0);
      s.V.row(j * (n + 1) + i) = (rotation * local + centre).transpose();
      s.N.row(j * (n + 1) + i) = normal.transpose();
    }
  }
  int f = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      s.F.row(f++) << a, a + 1, a + n + 2;
      s.F.row(f++) << a, a + n + 2, a + n + 1;
    }
  }
  return s;
}

// Row and column of the pixel that contains the projection of a world point.
struct PixelPosition {
  int row;
  int column;
};

inline PixelPosition project(const Camera& camera, int width, int height,
                             const Eigen::Vector3d& point) {
  const Eigen::Vector4d clip = projection_matrix(camera, static_cast<double>(width) / height) *
                               view_matrix(camera) * point.homogeneous();
  const Eigen::Vector2d ndc = clip.head<2>() / clip.w();
  return {static_cast<int>(std::floor(0.5 * (1.0 - ndc.y()) * height)),
          static_cast<int>(std::floor(0.5 * (ndc.x() + 1.0) * width))};
}

// The ray from the camera through the centre of pixel (row, column): unit direction.
inline Eigen::Vector3d pixel_ray(const Camera& camera, int width, int height, int row, int column) {
  const Eigen::Vector3d forward = (camera.target - camera.eye).normalized();
  const Eigen::Vector3d right = forward.cross(camera.up).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  const double half = std::tan(camera.fov_y_deg * std::numbers::pi / 360.0);
  const double x = (2.0 * (column + 0.5) / width - 1.0) * half * width / height;
  const double y = (1.0 - 2.0 * (row + 0.5) / height) * half;
  return (forward + x * right + y * up).normalized();
}

inline Pixel pixel_at(const std::vector<std::uint8_t>& rgb, int width, int row, int column) {
  const std::size_t i = (static_cast<std::size_t>(row) * width + column) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

// The lighting formula documented on SceneStyle, in 8-bit units before rounding; n is the normal
// already turned towards the camera, v the unit direction to the camera.
inline Eigen::Vector3d shade(const SceneStyle& style, const SurfaceLook& look,
                             const Eigen::Vector3d& n, const Eigen::Vector3d& v) {
  const Eigen::Vector3d l = style.to_light.normalized();
  const double lambert = std::max(0.0, n.dot(l));
  const double highlight =
      lambert > 0.0 ? std::pow(std::max(0.0, n.dot((l + v).normalized())), look.shininess) : 0.0;
  const Eigen::Vector3d colour =
      look.albedo.cast<double>() * (style.ambient + style.diffuse * lambert) +
      Eigen::Vector3d::Constant(look.specular * highlight);
  return 255.0 * colour.cwiseMax(0.0).cwiseMin(1.0);
}

// Largest channel difference between a pixel and an expected colour.
inline double colour_error(const Pixel& actual, const Eigen::Vector3d& expected) {
  double error = 0.0;
  for (int c = 0; c < 3; ++c)
    error = std::max(error, std::abs(actual[c] - expected[c]));
  return error;
}

}  // namespace incise::render::test
