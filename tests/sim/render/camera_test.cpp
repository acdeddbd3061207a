#include "sim/render/camera.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <stdexcept>

namespace incise::render {
namespace {

// Normalised device coordinates of a world point.
Eigen::Vector3d to_ndc(const Camera& camera, double aspect, const Eigen::Vector3d& point) {
  const Eigen::Vector4d clip =
      projection_matrix(camera, aspect) * view_matrix(camera) * point.homogeneous();
  return clip.head<3>() / clip.w();
}

Camera oblique_camera() {
  Camera camera;
  camera.eye = Eigen::Vector3d(0.3, -0.2, 0.4);
  camera.target = Eigen::Vector3d(0.05, 0.1, -0.02);
  camera.up = Eigen::Vector3d(0.0, 0.0, 2.0);  // length must not matter
  camera.fov_y_deg = 50.0;
  camera.near_m = 0.05;
  camera.far_m = 3.0;
  return camera;
}

TEST(Camera, ViewIsARigidMotionTakingEyeToOrigin) {
  const Camera camera = oblique_camera();
  const Eigen::Matrix4d view = view_matrix(camera);
  const Eigen::Matrix3d rotation = view.topLeftCorner<3, 3>();
  EXPECT_TRUE((rotation * rotation.transpose()).isIdentity(1e-12));
  EXPECT_NEAR(rotation.determinant(), 1.0, 1e-12);
  EXPECT_TRUE((view * camera.eye.homogeneous()).head<3>().isZero(1e-12));
  // The camera looks down -z.
  const Eigen::Vector3d target_eye = (view * camera.target.homogeneous()).head<3>();
  EXPECT_NEAR(target_eye.z(), -(camera.target - camera.eye).norm(), 1e-12);
}

TEST(Camera, TargetAtCentreUpAtTopRightAtRight) {
  const Camera camera = oblique_camera();
  const double aspect = 1.5;
  EXPECT_TRUE(to_ndc(camera, aspect, camera.target).head<2>().isZero(1e-12));
  const Eigen::Vector3d forward = (camera.target - camera.eye).normalized();
  const Eigen::Vector3d right = forward.cross(camera.up).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  const Eigen::Vector3d above = to_ndc(camera, aspect, camera.target + 0.01 * up);
  EXPECT_GT(above.y(), 0.0);
  EXPECT_NEAR(above.x(), 0.0, 1e-12);
  const Eigen::Vector3d beside = to_ndc(camera, aspect, camera.target + 0.01 * right);
  EXPECT_GT(beside.x(), 0.0);
  EXPECT_NEAR(beside.y(), 0.0, 1e-12);
}

TEST(Camera, ClipPlanesMapToDepthLimitsAndFovToFrameEdge) {
  Camera camera;  // looks down -z from (0, 0, 0.5)
  camera.fov_y_deg = 90.0;
  const double aspect = 2.0;
  const double at_near = camera.eye.z() - camera.near_m;
  const double at_far = camera.eye.z() - camera.far_m;
  EXPECT_NEAR(to_ndc(camera, aspect, Eigen::Vector3d(0, 0, at_near)).z(), -1.0, 1e-9);
  EXPECT_NEAR(to_ndc(camera, aspect, Eigen::Vector3d(0, 0, at_far)).z(), 1.0, 1e-9);
  // With a 90 degree field of view, a point as far up as it is ahead sits on the top edge,
  // and the horizontal extent is aspect times wider.
  EXPECT_NEAR(to_ndc(camera, aspect, Eigen::Vector3d(0, 0.3, 0.2)).y(), 1.0, 1e-12);
  EXPECT_NEAR(to_ndc(camera, aspect, Eigen::Vector3d(0.6, 0, 0.2)).x(), 1.0, 1e-12);
}

TEST(Camera, RejectsDegenerateSettings) {
  Camera camera;
  camera.target = camera.eye;
  EXPECT_THROW(view_matrix(camera), std::invalid_argument);
  camera = Camera();
  camera.up = Eigen::Vector3d(0, 0, -3);  // along the view direction
  EXPECT_THROW(view_matrix(camera), std::invalid_argument);
  camera.up = Eigen::Vector3d::Zero();
  EXPECT_THROW(view_matrix(camera), std::invalid_argument);
  camera = Camera();
  EXPECT_THROW(projection_matrix(camera, 0.0), std::invalid_argument);
  camera.fov_y_deg = 180.0;
  EXPECT_THROW(projection_matrix(camera, 1.0), std::invalid_argument);
  camera = Camera();
  camera.far_m = camera.near_m;
  EXPECT_THROW(projection_matrix(camera, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace incise::render
