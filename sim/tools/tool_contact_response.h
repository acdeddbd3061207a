#pragma once

// Penalty response of a tool (sphere tip or capsule shaft) against the surface triangles of a
// deformable body. The contacts come from a SurfaceBvh over the body's current
// positions (sim/collide/surface_bvh.h); each one pushes the tool out along its normal n (from
// the tissue to the tool) and the tissue back:
//   f_c = max(0, k_c depth_c - c_c (u_p - v_p) . n_c) n_c   force on the tool [N] (no adhesion)
//   node j of the touched triangle gets -w_j f_c, w the contact point's barycentric weights,
// with v_p = sum_j w_j v_j the velocity of the touched point and u_p the tool's velocity there.
// Since sum_j w_j = 1 and sum_j w_j x_j = the contact point, the node forces sum to -f_c and have
// no moment about the contact point: the tool's reaction is exact (Newton's third law, and the
// moment balance of a force applied at the point).
//
// The stiffness rule (why a penalty per mass and step, not a fixed N/m): with the lumped masses
// m_j of the touched triangle's nodes and the explicit step dt,
//   k_c = beta m_c / dt^2,   c_c = 2 zeta sqrt(k_c m_c) = 2 zeta sqrt(beta) m_c / dt,
//   m_c = min_j m_j  (constant per triangle, so that the force model's derivative is exact).
// One contact alone then removes about beta of its depth per step on any tissue and any mesh:
// a stiff tissue has a small CFL step, hence a large k_c, a soft one a small k_c. The bound: in
// mass-weighted coordinates a contact adds the rank-one k_c a a^T, |a|^2 = sum_j w_j^2 / m_j
// <= 1 / m_c, so its eigenvalue is <= beta / dt^2; contacts sharing nodes add up to at most
//   (omega dt)^2 <= beta s,   damping c dt / m <= 2 zeta sqrt(beta) s,
// s the largest number of contacts at one node (<= the triangles around a surface node: 4 to 8
// on the box meshes, one contact per triangle). Symplectic Euler on a damped oscillator is stable
// while c dt / m + (omega dt)^2 < 4 (Jury's conditions); the elastic part at the CFL step with
// safety 0.5 takes up to ~1.2 (stable_time_step.h), so the defaults beta = 0.1, zeta = 0.2 stay
// below 4 for s <= 10: 0.1 s + 0.126 s + 1.2.
// The price: such a penalty is only about as stiff as an element, so a tool pressed into soft,
// coarse tissue sinks into its surface (1.08 mm of a 2 mm press on a 3 kPa block with 3.3 mm
// cells); the force is still the tissue's reaction to the deformation it makes
// (tests/sim/tools/tool_contact_response_static_test.cpp). The haptic probe (probe.h) pushes with
// its coupling force instead and does not sink.

#include <vector>

#include "sim/collide/contact.h"
#include "sim/collide/surface_bvh.h"
#include "sim/collide/tool_shapes.h"
#include "sim/core/types.h"

namespace incise::sim::tools {

struct PenaltySettings {
  Real time_step = 0;             // dt of the explicit step the contact must be stable at [s], > 0
  Real stiffness_fraction = 0.1;  // beta, in (0, 1]
  Real damping_ratio = 0.2;       // zeta, >= 0
};

// Throws std::invalid_argument naming the bad field.
void validate(const PenaltySettings& settings);

// One contact and what it did.
struct ContactForce {
  collide::Contact contact;           // point, normal (tissue to tool), depth, triangle, weights
  Vec3i nodes = Vec3i::Constant(-1);  // the triangle's node indices (rows of x)
  Real stiffness = 0;                 // k_c [N/m]
  Real damping = 0;                   // c_c [N s/m]
  Vec3 elastic_force = Vec3::Zero();  // k_c depth n, on the tool [N]
  Vec3 force = Vec3::Zero();          // elastic + damping, on the tool [N]
};

// The sum over the contacts, on the tool.
struct ToolReaction {
  Vec3 force = Vec3::Zero();      // sum of f_c [N]
  Vec3 torque = Vec3::Zero();     // sum of (point_c - reference) x f_c [N m]
  Vec3 reference = Vec3::Zero();  // the sphere's centre, or the capsule's end a [m]
  int contacts = 0;
  Real max_depth = 0;  // [m]
};

// Keeps the per-step work arrays, so that a step allocates nothing once they have grown.
class ToolContactResponse {
 public:
  // Throws std::invalid_argument for bad settings.
  explicit ToolContactResponse(PenaltySettings settings);

  // Contacts of the tool with the surface at positions x (the bvh refitted to x), their forces
  // added to node_forces, the sum on the tool returned.
  //   bvh            the body's surface tree; its triangles index the rows of x
  //   x, v           #nodes by 3 positions [m] and velocities [m/s]
  //   masses         #nodes lumped masses [kg] (Model::masses())
  //   tool           the tool's shape this step (its effective pose: see swept_tool_motion.h)
  //   tool_velocity  the tool's translational velocity [m/s] (for the damping)
  //   node_forces    #nodes by 3 [N], the contact forces are added to it
  // Throws std::invalid_argument for a radius <= 0 or not finite, a non-finite pose or velocity,
  // or arrays whose sizes do not match.
  const ToolReaction& apply(const collide::SurfaceBvh& bvh, const Points& x, const Points& v,
                            const VecX& masses, const collide::Sphere& tool,
                            const Vec3& tool_velocity, Points& node_forces);
  const ToolReaction& apply(const collide::SurfaceBvh& bvh, const Points& x, const Points& v,
                            const VecX& masses, const collide::Capsule& tool,
                            const Vec3& tool_velocity, Points& node_forces);

  // The same without touching any node force: the contacts and their sum only (for a tool that
  // decides itself what it transmits, as the probe does; see distribute).
  const ToolReaction& evaluate(const collide::SurfaceBvh& bvh, const Points& x, const Points& v,
                               const VecX& masses, const collide::Sphere& tool,
                               const Vec3& tool_velocity);

  // Adds `force` [N] on the tissue, spread over the last evaluated contacts at least min_depth
  // deep [m] in proportion to their elastic forces (deeper and stiffer contacts carry more) and
  // within each contact by its barycentric weights: the node forces sum to `force` exactly and
  // have no moment about the contact points. Nothing without such contacts.
  // Throws std::invalid_argument if node_forces has fewer rows than the contacts index.
  void distribute(const Vec3& force, Points& node_forces, Real min_depth = 0) const;

  // The node weights of distribute(force, node_forces, min_depth): node j gets weight * force;
  // each node once, weights summing to 1; empty without such contacts. Into `weights` (cleared
  // first; no allocation once grown).
  struct NodeWeight {
    int node = -1;
    Real weight = 0;
  };
  void distribution_weights(std::vector<NodeWeight>& weights, Real min_depth = 0) const;

  // The contacts of the last apply or evaluate, and their sum.
  const std::vector<ContactForce>& contacts() const { return forces_; }
  const ToolReaction& reaction() const { return reaction_; }
  const PenaltySettings& settings() const { return settings_; }

 private:
  void respond(const collide::SurfaceBvh& bvh, const Points& x, const Points& v, const VecX& masses,
               const Vec3& reference, const Vec3& tool_velocity);
  void add_node_forces(Points& node_forces) const;

  PenaltySettings settings_;
  std::vector<collide::Contact> found_;
  std::vector<ContactForce> forces_;
  ToolReaction reaction_;
};

}  // namespace incise::sim::tools
