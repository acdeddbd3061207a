#include "grasp_fixtures.h"

#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/stable_time_step.h"

namespace incise::sim::tools::testing {

Scene scene_for(MaterialModel model) {
  Scene scene;
  scene.material.model = model;
  scene.material.youngs_modulus = kYoungs;
  scene.material.poisson_ratio = kPoisson;
  scene.material.density = kDensity;
  scene.material.damping = 0.3;
  return scene;
}

Real stable_dt(const TetMesh& mesh) {
  return stable_time_step(mesh, kYoungs, kPoisson, kDensity);
}

GraspedBlock::GraspedBlock(MaterialModel kind, const Vec3& size, const Vec3i& cells,
                           bool clamp_base)
    : mesh(make_box_mesh(size, cells)) {
  model = make_model(scene_for(kind), mesh);
  const VecX& m = model->masses();
  inverse_masses = m.cwiseInverse();
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (clamp_base && mesh.rest(i, 2) == 0) inverse_masses[i] = 0;
  }
  surface = boundary_surface(mesh).nodes;
  dt = stable_dt(mesh);
  forces = Points::Zero(mesh.num_nodes(), 3);
  prescribed.mask = AxisMask::Zero(mesh.num_nodes(), 3);
  prescribed.position = Points::Zero(mesh.num_nodes(), 3);
}

std::optional<ReleaseEvent> GraspedBlock::step(Grasper& grasper, const JawPose& pose) {
  std::optional<ReleaseEvent> event = grasper.set_jaws(pose);
  if (grasper.phase() == GraspPhase::closing) {
    grasper.grab(mesh.rest, mesh.x, inverse_masses, surface);
  }
  forces.setZero();
  model->add_forces(mesh.x, mesh.v, forces);
  if (auto torn = grasper.measure(forces)) event = torn;
  prescribed.mask.setZero();
  grasper.prescribe(prescribed);
  start_x = mesh.x;
  symplectic_euler_step(dt, Vec3::Zero(), inverse_masses, prescribed, forces, mesh.x, mesh.v);
  return event;
}

JawPose downward_jaws(const Vec3& pivot, Real opening_angle) {
  JawPose pose;
  pose.pivot = pivot;
  pose.direction = -Vec3::UnitZ();
  pose.opening_normal = Vec3::UnitX();
  pose.opening_angle = opening_angle;
  return pose;
}

}  // namespace incise::sim::tools::testing
