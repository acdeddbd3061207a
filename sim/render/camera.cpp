#include "sim/render/camera.h"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace incise::render {

Eigen::Matrix4d view_matrix(const Camera& camera) {
  const Eigen::Vector3d forward = camera.target - camera.eye;
  if (forward.norm() == 0.0) throw std::invalid_argument("camera eye and target coincide");
  const Eigen::Vector3d f = forward.normalized();
  const Eigen::Vector3d side = f.cross(camera.up);
  // Relative test (also catches a zero up): only the direction of up matters.
  if (side.norm() <= 1e-12 * camera.up.norm()) {
    throw std::invalid_argument("camera up is parallel to the view direction");
  }
  const Eigen::Vector3d s = side.normalized();
  const Eigen::Vector3d u = s.cross(f);

  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = s.transpose();
  view.block<1, 3>(1, 0) = u.transpose();
  view.block<1, 3>(2, 0) = -f.transpose();
  view.block<3, 1>(0, 3) = -view.block<3, 3>(0, 0) * camera.eye;
  return view;
}

Eigen::Matrix4d projection_matrix(const Camera& camera, double aspect) {
  if (!(aspect > 0.0)) throw std::invalid_argument("camera aspect must be positive");
  if (!(camera.fov_y_deg > 0.0 && camera.fov_y_deg < 180.0)) {
    throw std::invalid_argument("camera fov_y_deg must be in (0, 180)");
  }
  if (!(camera.near_m > 0.0 && camera.near_m < camera.far_m)) {
    throw std::invalid_argument("camera clip distances must satisfy 0 < near_m < far_m");
  }
  const double focal = 1.0 / std::tan(camera.fov_y_deg * std::numbers::pi / 360.0);
  const double n = camera.near_m;
  const double f = camera.far_m;
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  projection(0, 0) = focal / aspect;
  projection(1, 1) = focal;
  projection(2, 2) = (f + n) / (n - f);
  projection(2, 3) = 2.0 * f * n / (n - f);
  projection(3, 2) = -1.0;
  return projection;
}

}  // namespace incise::render
