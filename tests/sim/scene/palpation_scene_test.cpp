// The live demo scene sim/scenes/palpation.json: a block of soft tissue on a fixed base, probed
// with a sphere tool, stepped as the server's session thread steps it (contact, then one step).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/interact/tool_contact.h"
#include "sim/io/scene_json.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/scene/node_selection.h"
#include "sim/scene/simulation.h"

namespace incise::sim {
namespace {

struct Palpation {
  Scene scene = read_scene_file(INCISE_SCENES_DIR "/palpation.json");
  SphereTool tool = scene.tool.value();
  Simulation simulation{scene};
  BoundarySurface surface = boundary_surface(simulation.mesh());
  Points contact_forces = Points::Zero(simulation.mesh().num_nodes(), 3);
  ToolContact contact;

  Vec3 top_centre() const {
    const Vec3& size = scene.mesh.box.size;
    return Vec3(size.x() / 2, size.y() / 2, size.z());
  }
  void step(const Vec3& centre) {
    contact_forces.setZero();
    contact = apply_sphere_contact(tool, centre, surface, simulation.mesh().x, contact_forces);
    simulation.step(contact_forces);
  }
  int steps_for(Real seconds) const {
    return static_cast<int>(std::lround(seconds / scene.solver.dt));
  }
};

TEST(PalpationScene, SubStepsDivideTheServerTickAndAreStableWithTheTool) {
  const Palpation p;
  const Real tick = 0.002;  // [s]
  const Real sub_steps = tick / p.scene.solver.dt;
  EXPECT_EQ(sub_steps, std::round(sub_steps));
  // Per node, Gershgorin bounds on the highest frequency and damping rate of the free nodes with
  // the tool's penalty on top: omega^2 <= (k_tool + 2 sum k_ij) / m_i, gamma <= 2 sum c_ij / m_i.
  // Symplectic Euler on x'' = -omega^2 x - gamma x' is stable iff
  // 2 gamma dt + omega^2 dt^2 < 4 (Jury's conditions on its 2 by 2 step matrix).
  const MassSpring& model = p.simulation.model();
  const int n = p.simulation.mesh().num_nodes();
  VecX k_sum = VecX::Zero(n), c_sum = VecX::Zero(n);
  for (int s = 0; s < model.num_springs(); ++s) {
    for (int e = 0; e < 2; ++e) {
      k_sum(model.springs()(s, e)) += model.stiffness()(s);
      c_sum(model.springs()(s, e)) += model.damping()(s);
    }
  }
  const Real dt = p.scene.solver.dt;
  Real worst = 0;
  for (const int i : p.surface.nodes) {
    const Real m = model.masses()(i);
    const Real omega2 = (p.tool.stiffness + 2 * k_sum(i)) / m;
    const Real gamma = 2 * c_sum(i) / m;
    worst = std::max(worst, 2 * gamma * dt + omega2 * dt * dt);
  }
  EXPECT_LT(worst, 3.0) << "bound 4, kept with a margin for the tool's tangential terms";
}

TEST(PalpationScene, ProbePressedIntoTheTopSettlesAndIsPushedBackUp) {
  Palpation p;
  const Real press = 0.006;  // [m] below the rest top surface
  const Vec3 touching = p.top_centre() + Vec3(0, 0, p.tool.radius);
  const Vec3 pressed = touching - Vec3(0, 0, press);
  const int lower = p.steps_for(0.2);
  for (int s = 1; s <= lower; ++s)
    p.step(touching + (pressed - touching) * s / lower);
  for (int s = p.steps_for(1.5); s > 0; --s)
    p.step(pressed);
  ASSERT_TRUE(p.simulation.state_finite());
  EXPECT_LT(p.simulation.max_speed(), 1e-4);  // [m/s]: at rest
  const Vec3 force = p.contact.force_on_tool;
  EXPECT_GT(p.contact.nodes_in_contact, 0);
  EXPECT_LT(force.head<2>().norm(), 1e-3 * force.z());  // straight up on a symmetric block
  // A rigid flat punch of radius a pressed delta into an elastic half-space needs
  // F = 2 a E delta / (1 - nu^2) (Boussinesq); with a = the tool radius and delta = 6 mm,
  // 0.24 N. The penalty lets the tool sink into the tissue, so the tissue is pressed less than
  // 6 mm, and the mass-spring model resolves the tool with few nodes: expect the same order.
  const Material& material = p.scene.material;
  const Real punch = 2 * p.tool.radius * material.youngs_modulus * press /
                     (1 - material.poisson_ratio * material.poisson_ratio);
  EXPECT_GT(force.z(), 0.1 * punch);
  EXPECT_LT(force.z(), 2 * punch);
  // At rest the fixed base carries the tissue's weight and the tool's push:
  // sum over fixed nodes of the internal forces = m_free g - force_on_tool.
  const Points internal = p.simulation.internal_forces();
  const Prescribed& fixed = p.simulation.prescribed();
  Vec3 on_base = Vec3::Zero();
  Real free_mass = 0;
  for (int i = 0; i < p.simulation.mesh().num_nodes(); ++i) {
    if (fixed.mask(i, 2)) {
      on_base += row3(internal, i);
    } else {
      free_mass += p.simulation.model().masses()(i);
    }
  }
  const Vec3 expected = free_mass * p.scene.gravity - force;
  EXPECT_LT((on_base - expected).norm(), 1e-3 * expected.norm())
      << "on base " << on_base.transpose() << ", expected " << expected.transpose();
}

TEST(PalpationScene, ToolSweptThroughTheBlockAtOneMetrePerSecondStaysFinite) {
  Palpation p;
  const Vec3& size = p.scene.mesh.box.size;
  // Through the middle of the block along x, entering and leaving through the side faces.
  const Vec3 start(-2 * p.tool.radius, size.y() / 2, size.z() / 2);
  const Vec3 velocity(1, 0, 0);  // [m/s]
  const int sweep = p.steps_for((size.x() + 4 * p.tool.radius) / velocity.x());
  Real peak = 0;
  int max_in_contact = 0;
  for (int s = 1; s <= sweep; ++s) {
    p.step(start + velocity * (s * p.scene.solver.dt));
    ASSERT_TRUE(p.simulation.state_finite()) << "step " << s;
    ASSERT_TRUE(p.contact.force_on_tool.allFinite());
    peak = std::max(peak, p.simulation.max_speed());
    max_in_contact = std::max(max_in_contact, p.contact.nodes_in_contact);
  }
  EXPECT_GT(max_in_contact, 0);  // it did hit the tissue
  EXPECT_GT(peak, 0.1);          // and shook it
  // With the tool gone, the block calms down again instead of blowing up.
  const Vec3 away(-1, -1, -1);
  for (int s = p.steps_for(1.0); s > 0; --s)
    p.step(away);
  ASSERT_TRUE(p.simulation.state_finite());
  EXPECT_LT(p.simulation.max_speed(), 1e-3 * peak);
}

}  // namespace
}  // namespace incise::sim
