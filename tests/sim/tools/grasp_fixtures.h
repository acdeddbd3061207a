#pragma once
// A clamped or free soft block driven by a Grasper with symplectic Euler, shared by the grasp
// tests (tests/sim/tools/grasp_*.cpp).

#include <memory>
#include <optional>
#include <vector>

#include "sim/mesh/tet_mesh.h"
#include "sim/models/model.h"
#include "sim/scene/scene.h"
#include "sim/solve/symplectic_euler.h"
#include "sim/tools/grasper.h"

namespace incise::sim::tools::testing {

constexpr Real kYoungs = 3000;  // soft tissue [Pa]
constexpr Real kPoisson = 0.3;
constexpr Real kDensity = 1000;  // [kg/m^3]

Scene scene_for(MaterialModel model);

// A box body stepped by symplectic Euler with a grasper's prescribed vertices, gravity off.
struct GraspedBlock {
  // size [m], cells per axis; `clamp_base` holds the z = 0 nodes (inverse mass 0).
  GraspedBlock(MaterialModel model, const Vec3& size, const Vec3i& cells, bool clamp_base);

  // One step to `pose`: set_jaws, grab when closing (the surface vertices), forces at the
  // current state, measure, prescribe, integrate. The event of the step, if any.
  std::optional<ReleaseEvent> step(Grasper& grasper, const JawPose& pose);

  TetMesh mesh;
  std::unique_ptr<Model> model;
  VecX inverse_masses;
  std::vector<int> surface;  // boundary vertices
  Real dt = 0;
  Points forces;   // the internal forces at the last step's start state
  Points start_x;  // the positions the last step started from
  Prescribed prescribed;
};

// The stable step of mesh for the test material (stable_time_step with its safety).
Real stable_dt(const TetMesh& mesh);

// Jaws pointing down (-z) from pivot, opening in x.
JawPose downward_jaws(const Vec3& pivot, Real opening_angle);

}  // namespace incise::sim::tools::testing
