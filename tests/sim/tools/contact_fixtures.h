#pragma once
// A corotational (polar) block with its surface tree, stepped by symplectic Euler with a tool's
// contact forces, shared by the contact tests (tests/sim/tools/contact_*.cpp).

#include <memory>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "sim/collide/surface_bvh.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/models/model.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim::tools::contact_testing {

constexpr Real kSoft = 3000;    // soft tissue, Young's modulus [Pa]
constexpr Real kStiff = 1.0e6;  // stiff tissue (cartilage-like) [Pa]
constexpr Real kPoisson = 0.3;
constexpr Real kDensity = 1000;  // [kg/m^3]

struct ContactBlock {
  //   size  [m], cells per axis (make_box_mesh); youngs [Pa]; beta the model's damping [s]
  //   clamp  which nodes are held (inverse mass 0): the z = 0 base, or the rim x or y at the box
  //          ends (a membrane held at its edges)
  enum class Clamp { base, rim };
  ContactBlock(const Vec3& size, const Vec3i& cells, Real youngs, Clamp clamp, Real beta = 0);

  // The tree refitted to x; forces = internal forces at (x, v).
  void prepare();
  // symplectic Euler with `forces` (internal + whatever was added since prepare()).
  void integrate();

  Real kinetic_energy() const;
  Real potential_energy() const { return model->potential_energy(mesh.x); }
  // Sum of the internal forces on the held nodes, negated: what the supports push with [N].
  Vec3 support_reaction() const;

  TetMesh mesh;
  std::unique_ptr<Model> model;
  VecX inverse_masses;
  Triangles faces;  // boundary faces with mesh node indices
  collide::SurfaceBvh bvh;
  Real dt = 0;    // the CFL step (stable_time_step) [s]
  Points forces;  // #nodes by 3 [N]
  Prescribed prescribed;
};

// The message of the std::invalid_argument that f throws (fails the test if none).
template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::invalid_argument";
  return {};
}

}  // namespace incise::sim::tools::contact_testing
