#pragma once

// The local force model a haptic station renders between two simulation updates
// (devices/protocol.h's ForceModel frame): a force at a reference position and a stiffness,
//   F(c) = F0 - K (c - c0),   K symmetric positive semi-definite,
// so the agent's 1 kHz loop feels a smooth surface without waiting for the network. A force law
// with a symmetric PSD K is the gradient of the convex potential -F0 . c + (c - c0)^T K (c - c0) /
// 2, which the device renders passively; that is why K is the PSD part of the exact derivative, not
// the derivative itself (see exact_contact_stiffness for why the exact one is indefinite).

#include <vector>

#include "sim/collide/tool_shapes.h"
#include "sim/core/types.h"
#include "sim/tools/tool_contact_response.h"

namespace incise::sim::tools {

struct LocalForceModel {
  Vec3 reference_position = Vec3::Zero();  // c0, the tool (or device) position [m]
  Vec3 force = Vec3::Zero();               // F0, on the tool (or the hand) at c0 [N]
  Mat3 stiffness = Mat3::Zero();           // K [N/m], symmetric PSD

  Vec3 force_at(const Vec3& position) const {
    return force - stiffness * (position - reference_position);
  }
};

// -d/dc of the elastic contact force on the tool, sum_c k_c depth_c n_c, with the tissue's nodes
// held and the tool translated by c [N/m]. Exact per contact, from the closest features of the
// tool (sphere: its centre; capsule: an end, or an interior point of its axis) and of the triangle
// (a vertex, an edge or the face, read off the contact's barycentric weights):
//   K_c = k_c (n n^T - (depth / rho) P),   rho = radius - depth, the features' distance,
// P the projector onto the directions orthogonal to n and to both features' directions (a
// feature point moves with c, so n turns only in those). A sphere on a vertex gets P = I - n n^T,
// on an edge e the one direction n x e, on the face P = 0. Symmetric but indefinite: the
// tangential part is negative because a ball resting on a vertex or an edge is unstable sideways
// (moving it turns n so that the force pushes further the same way). A contact with rho ~ 0 (a
// capsule whose axis pierces the triangle) adds k_c n n^T.
//   contacts  ToolContactResponse::contacts() for this tool at x
//   x         #nodes by 3 positions [m] the contacts were found at
Mat3 exact_contact_stiffness(const std::vector<ContactForce>& contacts, const Points& x,
                             Real radius, const collide::Capsule* capsule = nullptr);

// The nearest symmetric PSD matrix in the Frobenius norm: negative eigenvalues set to 0 (Higham
// 1988, "Computing a nearest symmetric positive semidefinite matrix", theorem 2.1).
// Throws std::invalid_argument for a non-symmetric or non-finite matrix.
Mat3 positive_part(const Mat3& symmetric);

// The local model of a sphere tool's contacts at its centre: F0 = sum of the elastic contact
// forces (the damping is left out: it is a velocity term the device adds itself), K = the PSD
// part of exact_contact_stiffness.
// Throws std::invalid_argument as check_sphere (radius <= 0, non-finite centre).
LocalForceModel sphere_force_model(const std::vector<ContactForce>& contacts, const Points& x,
                                   const collide::Sphere& tool);
// The same for a capsule (translations of the whole capsule; its torque is not modelled).
LocalForceModel capsule_force_model(const std::vector<ContactForce>& contacts, const Points& x,
                                    const collide::Capsule& tool);

}  // namespace incise::sim::tools
