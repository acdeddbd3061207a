// Workspace mapping: devices/workspace_mapping.h. Every expectation is a closed form or an
// identity (round trips, virtual work), checked over many random configurations.

#include "devices/workspace_mapping.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "devices/device_state.h"
#include "devices/eigen_conversions.h"
#include "devices/protocol.h"
#include "kinematics_fixtures.h"

namespace incise::devices {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;

WorkspaceMapping random_mapping(Random& random) {
  return {random.uniform(0.2, 5.0), to_quat(random.rotation()), to_vec3(random.vector(0.5))};
}

TEST(WorkspaceMapping, MapsPointsAndRoundTrips) {
  Random random(1);
  for (int trial = 0; trial < 200; ++trial) {
    const WorkspaceMapping m = random_mapping(random);
    const Vector3d p = random.vector(0.3), q = random.vector(0.3);
    const Vector3d p_scene = to_eigen(m.to_scene(to_vec3(p)));
    // x_scene = R (s x) + o, written out with a rotation matrix.
    const Vector3d expected =
        to_eigen(m.rotation).toRotationMatrix() * (m.scale * p) + to_eigen(m.offset);
    EXPECT_LT((p_scene - expected).norm(), 1e-12);
    EXPECT_LT((to_eigen(m.to_device(to_vec3(p_scene))) - p).norm(), 1e-12);
    // Distances scale by s; displacements are differences of mapped points.
    const Vector3d q_scene = to_eigen(m.to_scene(to_vec3(q)));
    EXPECT_NEAR((p_scene - q_scene).norm(), m.scale * (p - q).norm(), 1e-12);
    const Vector3d d_scene = to_eigen(m.displacement_to_scene(to_vec3(p - q)));
    EXPECT_LT((d_scene - (p_scene - q_scene)).norm(), 1e-12);
    EXPECT_LT((to_eigen(m.displacement_to_device(to_vec3(d_scene))) - (p - q)).norm(), 1e-12);
  }
}

TEST(WorkspaceMapping, RotatesOrientationsAndRoundTrips) {
  Random random(2);
  for (int trial = 0; trial < 200; ++trial) {
    const WorkspaceMapping m = random_mapping(random);
    const Quaterniond q_device = random.rotation();
    const Quaterniond q_scene = to_eigen(m.orientation_to_scene(to_quat(q_device)));
    // A tool axis seen in the scene is the device's tool axis turned by R.
    const Vector3d axis = random.vector(1.0);
    EXPECT_LT((q_scene * axis - to_eigen(m.rotation) * (q_device * axis)).norm(), 1e-12);
    const Quaterniond back = to_eigen(m.orientation_to_device(to_quat(q_scene)));
    EXPECT_LT(back.angularDistance(q_device), 1e-12);
  }
}

TEST(WorkspaceMapping, MappedForcesDoTheSameVirtualWork) {
  Random random(3);
  for (int trial = 0; trial < 200; ++trial) {
    const WorkspaceMapping m = random_mapping(random);
    const Vector3d f_scene = random.vector(5.0);
    const Vector3d dx_device = random.vector(1e-3);
    const Vector3d f_device = to_eigen(m.force_to_device(to_vec3(f_scene)));
    const Vector3d dx_scene = to_eigen(m.displacement_to_scene(to_vec3(dx_device)));
    EXPECT_NEAR(f_device.dot(dx_device), f_scene.dot(dx_scene), 1e-14);
    EXPECT_NEAR(f_device.norm(), m.scale * f_scene.norm(), 1e-12);
    EXPECT_LT((to_eigen(m.force_to_scene(to_vec3(f_device))) - f_scene).norm(), 1e-12);
  }
}

TEST(WorkspaceMapping, ForceModelAgreesWithTheSceneModelEverywhere) {
  Random random(4);
  const auto force_at = [](const ForceModel& model, const Vector3d& x) {
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> k(model.stiffness.data());
    return Vector3d(to_eigen(model.force) - k * (x - to_eigen(model.reference_position)));
  };
  for (int trial = 0; trial < 50; ++trial) {
    const WorkspaceMapping m = random_mapping(random);
    ForceModel scene;
    scene.device_index = 1;
    scene.reference_position = to_vec3(random.vector(0.1));
    scene.force = to_vec3(random.vector(3.0));
    for (double& k : scene.stiffness)
      k = random.uniform(-500.0, 500.0);
    scene.state_timestamp_us = 77;
    const ForceModel device = m.force_model_to_device(scene);
    EXPECT_EQ(device.device_index, 1);
    EXPECT_EQ(device.state_timestamp_us, 77u);
    for (int point = 0; point < 10; ++point) {
      const Vector3d x = random.vector(0.1);
      const Vector3d expected =
          to_eigen(m.force_to_device(to_vec3(force_at(scene, to_eigen(m.to_scene(to_vec3(x)))))));
      EXPECT_LT((force_at(device, x) - expected).norm(), 1e-9 * (1.0 + expected.norm()));
    }
  }
}

TEST(WorkspaceMapping, StateToSceneMapsPoseOnly) {
  const WorkspaceMapping m{
      2.0, to_quat(Quaterniond(Eigen::AngleAxisd(kPi / 2, Vector3d::UnitZ()))), {0.1, 0.0, 0.0}};
  DeviceState device{1, 0b101, 0.25f, {0.01, 0.0, 0.0}, {}};
  const DeviceState scene = m.state_to_scene(device);
  EXPECT_EQ(scene.device_index, 1);
  EXPECT_EQ(scene.buttons, 0b101);
  EXPECT_EQ(scene.jaw, 0.25f);
  // 1 cm along x, doubled, turned a quarter about z, then offset: (0.1, 0.02, 0).
  EXPECT_NEAR(scene.position.x, 0.1, 1e-15);
  EXPECT_NEAR(scene.position.y, 0.02, 1e-15);
  EXPECT_NEAR(scene.position.z, 0.0, 1e-15);
  EXPECT_LT(to_eigen(scene.orientation).angularDistance(to_eigen(m.rotation)), 1e-15);
}

}  // namespace
}  // namespace incise::devices
