#pragma once

// A probe driven by a haptic device (issue 6 item 3): a sphere tip whose proxy follows the
// device through a virtual coupling and stops at the tissue surface.
//
// Virtual coupling (Colgate, Stanley, Brown 1995, "Issues in the haptic display of tool use")
// with a god-object proxy (Zilles and Salisbury 1995): a spring k_v joins the device position d
// to a massless proxy p; only the proxy touches the tissue. Each step, against the tissue as it
// is at the start of the step:
//  1. the proxy moves towards d through SweptToolMotion (swept_tool_motion.h): it never tunnels,
//     enters the tissue by at most allowed_penetration, slides along the surface, and is pushed
//     out when the tissue moves into it;
//  2. from the contacts found there (ToolContactResponse::evaluate), the point nearest to d with
//     the tip's core outside every contact's plane, (p - q_c) . n_c >= r - allowed_penetration,
//     is found (Dykstra's projections) and reached through the swept check again: on a flat
//     surface the proxy sits right above the hand, in the dimple a pressed tip makes it settles
//     where the walls hold it, rather than wedging against one wall;
//  3. being massless, the proxy passes the coupling's pull on to the tissue when it goes into
//     the surface (pull . n < 0, n the mean normal of the contacts the proxy rests on: the sum
//     of their elastic forces, normalised), spread over those contacts
//     (ToolContactResponse::distribute); nothing when it pulls out (no adhesion). At the nearest
//     free point the pull is balanced by the contact planes' normals (the projection's
//     optimality), so its side part, in a dimple, is the walls' reaction.
//     The pull is a spring k_v (d - p) from the device to the surface (the proxy rides on it),
//     far stiffer than an explicit step can carry on soft tissue (k_v dt^2 / m reaches ~5 for a
//     500 N/m device on a 3 kPa block with 4 mm cells: the tissue blows up), plus a damper b.
//     Both are integrated implicitly on the pushed point u (implicit_push in probe.cpp: effective
//     mass m, end-of-step velocity V1, device velocity v_d):
//       F = k_v (d - p) + b v_d - (k_v dt + b) V1,   b = 2 coupling_damping_ratio sqrt(k_v m),
//     unconditionally stable for that point and equal to k_v (d - p) at rest. V1 needs the other
//     forces on the nodes: node_forces must hold them (internal, external) when step is called.
// The hand feels what the proxy passes on, H = -F (k_v (p - d) when not pushing: 0 in free
// space). At rest the tissue carries exactly what the hand pushes with (the support reactions
// equal H), whatever the tissue's stiffness or the penalty's, and |H| stays near k_v |p - d|:
// choose k_v within what the device renders.
// Local force model for the station agent (force_model.h's LocalForceModel, at d): F0 = H and,
// while the proxy pushes, K = k_v P, P the projector onto the normals of the contacts the proxy
// rests on (core on their plane). That is the exact derivative of the spring force k_v (p - d)
// for the tissue held: moving the hand along those normals leaves the proxy in place, moving it
// along the others moves the proxy with it. On a flat surface K = k_v n n^T; in a coarse dimple
// whose walls block every direction, k_v I; free, K = 0. Symmetric PSD, never stiffer than k_v.
//
// Refinement hook: contact_region() says where the probe touches, in the rest configuration
// (each contact's barycentric point mapped through the rest positions of its triangle), so an
// adaptive body can refine there (this library does not link the remesher).

#include <vector>

#include "sim/collide/surface_bvh.h"
#include "sim/core/types.h"
#include "sim/tools/force_model.h"
#include "sim/tools/swept_tool_motion.h"
#include "sim/tools/tool_contact_response.h"

namespace incise::sim::tools {

struct ProbeSettings {
  Real radius = 0.004;                // tip radius [m], > 0
  Real coupling_stiffness = 500;      // k_v [N/m], > 0
  Real coupling_damping_ratio = 1;    // zeta of the coupling's damper on the pushed tissue, >= 0
  Real allowed_penetration = 0.0005;  // per step [m], in (0, radius)
  // The coupling saturates here [N], > 0: a desktop haptic device renders a few newtons, and a
  // device driven deep into the tissue (a violent hand) must not pull it apart with the spring's
  // unbounded force. Both the push on the tissue and the hand's force are capped.
  Real max_force = 4;
  PenaltySettings contact;  // the tip's penalty (its time_step is the step dt)
};

// Where the probe touches, in the rest configuration.
struct ContactRegion {
  bool touching = false;
  Vec3 centre = Vec3::Zero();  // the depth-weighted mean of the contacts' rest points [m]
  Real radius = 0;  // the farthest contact rest point from centre, plus the tip radius [m]
};

class Probe {
 public:
  // The proxy and the device start at `position` [m].
  // Throws std::invalid_argument for bad settings or a non-finite position.
  Probe(ProbeSettings settings, const Vec3& position);

  // One simulation step of the settings' time_step: the device is at device_position; the body's
  // surface tree is refitted to x. Moves the proxy, adds the push on the tissue to node_forces
  // (#nodes by 3 [N]; on entry it must hold the step's other forces on the nodes, the model's
  // internal forces included, for the implicit push) and updates the force models.
  //   x, v     #nodes by 3 positions [m] and velocities [m/s];  masses  #nodes lumped [kg]
  // Allocates nothing once its work arrays have grown.
  // Throws std::invalid_argument for a non-finite device position or mismatched arrays.
  void step(const Vec3& device_position, const collide::SurfaceBvh& bvh, const Points& x,
            const Points& v, const VecX& masses, Points& node_forces);

  const Vec3& proxy() const { return proxy_; }
  const Vec3& device() const { return device_; }
  collide::Sphere tip() const { return {proxy_, settings_.radius}; }
  // The force on the hand [N]: what the massless proxy passes on, i.e. minus the push on the
  // tissue while it pushes; k_v (p - d) otherwise (0 in free space, where p = d).
  const Vec3& hand_force() const { return hand_force_; }
  // The proxy's penalty contacts at the last step (they locate the contact and weigh its
  // distribution; their forces are not applied, see the header).
  const ToolReaction& reaction() const { return response_.reaction(); }
  // The force the proxy passed on to the tissue at the last step [N].
  const Vec3& transmitted_force() const { return transmitted_; }
  const std::vector<ContactForce>& contacts() const { return response_.contacts(); }
  // What the station agent renders: the model at the device position (see the header).
  const LocalForceModel& hand_force_model() const { return hand_model_; }
  // Whether the last step's motion was stopped by the surface.
  bool blocked() const { return blocked_; }

  // The contact region of the last step. rest: #nodes by 3 rest positions [m] (the mesh's rest).
  // Throws std::invalid_argument if rest has too few rows.
  ContactRegion contact_region(const Points& rest) const;

  const ProbeSettings& settings() const { return settings_; }

 private:
  ProbeSettings settings_;
  ToolContactResponse response_;
  SweptToolMotion motion_;
  Vec3 proxy_;
  Vec3 device_;
  // Dykstra sweeps for nearest_free_position (a pocket has a handful of active contacts; the
  // iteration stops early once nothing moves).
  static constexpr int kProjectionSweeps = 50;
  Vec3 nearest_free_position();
  Vec3 implicit_push(const Vec3& pull, const Vec3& device_velocity, const Points& v,
                     const VecX& masses, const Points& other_forces, Real min_depth);
  Mat3 blocked_projector() const;

  LocalForceModel hand_model_;
  std::vector<Vec3> corrections_;
  std::vector<ToolContactResponse::NodeWeight> weights_;
  Vec3 transmitted_ = Vec3::Zero();
  Vec3 hand_force_ = Vec3::Zero();
  bool blocked_ = false;
};

}  // namespace incise::sim::tools
