#pragma once

#include "sim/core/types.h"
#include "sim/interact/sphere_tool.h"
#include "sim/mesh/boundary_surface.h"

namespace incise::sim {

// What a contact did to the tool.
struct ToolContact {
  Vec3 force_on_tool = Vec3::Zero();  // sum of reactions [N]
  // K with force_on_tool(c) ~= force_on_tool(c0) - K (c - c0): the local force model's
  // linearisation, symmetric PSD. It is the positive semi-definite part of exact_stiffness (its
  // negative eigenvalues clamped to 0), because a haptic device can render a force law
  // F0 - K (c - c0) passively (stably) only for K PSD; see exact_stiffness for why the exact one
  // is not. Its largest eigenvalue is at most tool.stiffness * nodes_in_contact.
  Mat3 stiffness = Mat3::Zero();
  int nodes_in_contact = 0;
  Real max_depth = 0;  // [m]
  // -d force_on_tool / d centre with the nodes held [N/m], exact and symmetric but indefinite:
  // per node k (n n^T - (d / |x_i - c|) (I - n n^T)). The tangential part is negative because a
  // sphere resting on a point is unstable sideways (it rolls off): moving the centre sideways
  // turns n so that the reaction pushes further the same way.
  Mat3 exact_stiffness = Mat3::Zero();
};

// Penalty contact of a sphere tool (centre c, radius r, stiffness k) with the surface nodes. For
// every surface node i strictly inside the sphere, with rho = |x_i - c| > 0:
//   depth d = r - rho,  n = (x_i - c) / rho,  f_i = k d n on the node,  -f_i on the tool.
// A node within 1e-9 r of the centre has no defined direction; it is pushed along +z (out of a
// tissue's upper surface, where a probe comes from) and adds only k n n^T to the stiffness, so
// nothing is NaN. The reaction sums cancel the node forces exactly (Newton's third law).
//   tool         radius, stiffness; damping is not used here (it needs velocities: see below)
//   centre       c [m]
//   surface      boundary_surface of the mesh x belongs to
//   x            #nodes by 3 positions [m]
//   node_forces  #nodes by 3 [N], the contact forces are added to it
// Allocates nothing.
ToolContact apply_sphere_contact(const SphereTool& tool, const Vec3& centre,
                                 const BoundarySurface& surface, const Points& x,
                                 Points& node_forces);

// The same plus normal damping: each node in contact also gets -tool.damping ((v_i - u) . n) n,
// where u is the tool's velocity, and the tool the opposite, so that the contact dissipates
// energy when nodes move into or out of the sphere. The stiffness terms are those of the
// elastic part (damping depends on velocities, not on the centre).
//   tool_velocity  u [m/s];  v  #nodes by 3 velocities [m/s]
ToolContact apply_sphere_contact(const SphereTool& tool, const Vec3& centre,
                                 const Vec3& tool_velocity, const BoundarySurface& surface,
                                 const Points& x, const Points& v, Points& node_forces);

}  // namespace incise::sim
