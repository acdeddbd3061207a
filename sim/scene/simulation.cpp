#include "sim/scene/simulation.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/mesh/box_mesher.h"
#include "sim/scene/node_selection.h"
#include "sim/scene/scene_error.h"
#include "sim/scene/scene_validation.h"

namespace incise::sim {
namespace {

TetMesh make_mesh(const Scene& scene) {
  validate_scene(scene);  // before anything is allocated from the scene's numbers
  // This class is the real-time path (live sessions): a box of mass-springs stepped by symplectic
  // Euler. Other meshes, models and integrators run through sim/scene/scene_run.h.
  if (scene.mesh.source != MeshSource::box) {
    throw SceneError("mesh", "a live simulation needs mesh.box");
  }
  if (scene.material.model != MaterialModel::mass_spring) {
    throw SceneError("material.model", "a live simulation needs \"mss\"");
  }
  if (scene.solver.integrator != Integrator::symplectic_euler) {
    throw SceneError("solver.integrator", "a live simulation needs \"symplectic_euler\"");
  }
  try {
    return make_box_mesh(scene.mesh.box.size, scene.mesh.box.cells);
  } catch (const std::invalid_argument& error) {
    throw SceneError("mesh", error.what());
  }
}

// Valid numbers can still give unusable tets, e.g. a box so small that the volumes underflow.
MassSpring make_model(const TetMesh& mesh, const Material& material) {
  try {
    return MassSpring(mesh.rest, mesh.tets,
                      {material.youngs_modulus, material.density, material.damping});
  } catch (const std::invalid_argument& error) {
    throw SceneError("mesh", error.what());
  }
}

std::vector<int> select(const TetMesh& mesh, const Selection& where, const std::string& path) {
  std::vector<int> nodes = nodes_in_box(mesh.rest, where.box, selection_tolerance(mesh.rest));
  if (nodes.empty()) throw SceneError(path + ".box", "selects no node");
  return nodes;
}

}  // namespace

Simulation::Simulation(const Scene& scene)
    : mesh_(make_mesh(scene)),
      model_(make_model(mesh_, scene.material)),
      gravity_(scene.gravity),
      dt_(scene.solver.dt),
      ramp_steps_(std::max<std::int64_t>(1, scene.solver.steps / 2)) {
  const Eigen::Index n = mesh_.num_nodes();
  inv_mass_ = (model_.masses().array() > 0).select(model_.masses().cwiseInverse(), 0.0);

  prescribed_.mask = AxisMask::Zero(n, 3);
  prescribed_.position = mesh_.rest;
  prescribed_displacement_ = Points::Zero(n, 3);
  for (std::size_t c = 0; c < scene.constraints.size(); ++c) {
    const Constraint& constraint = scene.constraints[c];
    const std::string path = "constraints[" + std::to_string(c) + "].where";
    for (const int i : select(mesh_, constraint.where, path)) {
      for (int a = 0; a < 3; ++a) {
        if (!constraint.axes[static_cast<std::size_t>(a)]) continue;
        prescribed_.mask(i, a) = 1;
        prescribed_displacement_(i, a) = constraint.displacement(a);
      }
    }
  }
  ramping_ = !prescribed_displacement_.isZero(0);

  external_forces_ = Points::Zero(n, 3);
  for (std::size_t l = 0; l < scene.loads.size(); ++l) {
    const Load& load = scene.loads[l];
    const std::vector<int> nodes =
        select(mesh_, load.where, "loads[" + std::to_string(l) + "].where");
    const Vec3 share = load.force / static_cast<Real>(nodes.size());
    for (const int i : nodes)
      external_forces_.row(i) += share.transpose();
  }
  forces_ = Points::Zero(n, 3);
}

void Simulation::update_prescribed_positions() {
  if (!ramping_ || steps_taken_ >= ramp_steps_) return;  // held since the end of the ramp
  const Real scale = static_cast<Real>(steps_taken_ + 1) / static_cast<Real>(ramp_steps_);
  prescribed_.position.noalias() = mesh_.rest + scale * prescribed_displacement_;
}

void Simulation::step() {
  forces_ = external_forces_;
  advance();
}

void Simulation::step(const Points& additional_forces) {
  if (additional_forces.rows() != mesh_.num_nodes()) {
    throw std::invalid_argument("additional forces have " +
                                std::to_string(additional_forces.rows()) + " rows for " +
                                std::to_string(mesh_.num_nodes()) + " nodes");
  }
  forces_ = external_forces_ + additional_forces;
  advance();
}

// The rest of a step once forces_ holds the external forces.
void Simulation::advance() {
  model_.add_forces(mesh_.x, mesh_.v, forces_);
  update_prescribed_positions();
  symplectic_euler_step(dt_, gravity_, inv_mass_, prescribed_, forces_, mesh_.x, mesh_.v);
  ++steps_taken_;
}

SimulationState Simulation::save_state() const {
  return {mesh_.x, mesh_.v, steps_taken_};
}

void Simulation::restore_state(const SimulationState& state) {
  const auto check = [this](const Points& array, const char* name) {
    if (array.rows() != mesh_.num_nodes()) {
      throw std::invalid_argument(std::string("state ") + name + " have " +
                                  std::to_string(array.rows()) + " rows for " +
                                  std::to_string(mesh_.num_nodes()) + " nodes");
    }
  };
  check(state.positions, "positions");
  check(state.velocities, "velocities");
  if (state.steps_taken < 0) {
    throw std::invalid_argument("state steps_taken is negative (" +
                                std::to_string(state.steps_taken) + ")");
  }
  mesh_.x = state.positions;  // same size: no allocation
  mesh_.v = state.velocities;
  steps_taken_ = state.steps_taken;
  // The prescribed positions as the uninterrupted run left them after step steps_taken - 1 (the
  // rest before the first step); the same expression as update_prescribed_positions, so that the
  // values are bitwise the same.
  if (ramping_) {
    const std::int64_t ramped = std::min(steps_taken_, ramp_steps_);
    const Real scale = static_cast<Real>(ramped) / static_cast<Real>(ramp_steps_);
    prescribed_.position.noalias() = mesh_.rest + scale * prescribed_displacement_;
  }
}

Real Simulation::max_speed() const {
  if (!mesh_.v.allFinite()) return std::numeric_limits<Real>::quiet_NaN();
  return mesh_.num_nodes() == 0 ? 0 : mesh_.v.rowwise().norm().maxCoeff();
}

bool Simulation::state_finite() const {
  return mesh_.x.allFinite() && mesh_.v.allFinite();
}

Points Simulation::internal_forces() const {
  Points forces = Points::Zero(mesh_.num_nodes(), 3);
  model_.add_forces(mesh_.x, mesh_.v, forces);
  return forces;
}

}  // namespace incise::sim
