#pragma once

// A probe driven by a haptic device: a sphere tip whose proxy follows the
// device through a virtual coupling and stops at the tissue surface.
//
// Virtual coupling (Colgate, Stanley, Brown 1995, "Issues in the haptic display of tool use")
// with a massless proxy (after Zilles and Salisbury 1995's god-object): a spring k_v joins the
// device position d to the proxy p; only the proxy touches the tissue. Each step, against the
// tissue as it is at the start of the step:
//  1. the proxy moves towards d through SweptToolMotion (swept_tool_motion.h): it never tunnels,
//     enters the tissue by at most allowed_penetration, slides along the surface, and is pushed
//     out when the tissue moves into it; then to the point nearest d with the tip's core outside
//     every contact's plane, (p - q_c) . n_c >= r - allowed_penetration (Dykstra's projections),
//     through the sweep again: it seats on the surface, in a dimple where the walls hold it, and
//     never stays behind the surface (without this seat, a proxy the tissue had engulfed in a
//     jerk stayed trapped inside, agitating it); call that point p0;
//  2. the contacts there (ToolContactResponse::evaluate: normal n_c from the tissue to the tool,
//     triangle nodes j with barycentric weights b_cj) push the proxy out with lambda_c n_c and the
//     tissue in with -lambda_c n_c, solved implicitly for the end of the step: the nodes move by
//     dt v_j + dt^2 (g_j + f_j) / m_j in the step (symplectic Euler; g_j the other forces on the
//     node, f_j the contacts'), so contact c's depth at the end of the step is
//       depth_c = e_c - n_c . (p - p0) - dt^2 sum_d G_cd lambda_d,
//       e_c = its depth now + n_c . sum_j b_cj (dt v_j + dt^2 g_j / m_j),
//       G_cd = sum_j b_cj b_dj (n_c . n_d) / m_j   (the contacts' inverse mass),
//     the penalty is lambda_c = k_c depth_c (k_c = contact_stiffness_ratio k_v), and the massless
//     proxy balances, k_v (d - p) + sum_c lambda_c n_c = 0. That is linear in (p, lambda):
//       A = I + dt^2 K G,  M = N^T A^-1 K N,  (k_v I + M) (p - p0) = k_v (d - p0) + N^T A^-1 K e,
//       lambda = A^-1 K (e - N (p - p0));
//     a contact with lambda_c < 0 would pull (adhesion): it leaves and the rest is solved again;
//  3. the tissue gets -lambda_c n_c at each contact, spread by the barycentric weights.
// Implicit in the contacts, the push is stable however stiff the contact and however light the
// nodes, and it is a function of the state (no contact set picked by a threshold). Two earlier
// designs: an explicit penalty (scaled by the node masses to stay stable, so on light nodes a
// 500 N/m device sank millimetres in), then the pull spread over the contacts the proxy's core
// rested on (where the triangles were smaller than the tip, a refined region or an 8 mm tip on
// the liver's 10 mm cells, that set switched from step to step and the nodes under a held tip
// chattered at up to 1 m/s).
// The hand feels the coupling, H = k_v (p - d), saturated at max_force (the balance then caps the
// spring's force at p0). The proxy reaches p through the swept check (no tunnelling), and
// the contacts' forces follow where it actually went. At rest the tissue carries exactly what the
// hand pushes with.
// Local force model for the station agent (force_model.h's LocalForceModel, at d): F0 = H and
// K_h = k_v (k_v I + M)^-1 M, the derivative of H in d through the balance (the coupling in
// series with the contacts over one step): nearly k_v along the contact normals, 0 free, never
// stiffer than k_v; symmetric PSD (M and k_v I + M commute). Saturated, K_h = 0.
//
// Refinement hook: contact_region() says where the probe touches, in the rest configuration
// (each contact's barycentric point mapped through the rest positions of its triangle), so an
// adaptive body can refine there (this library does not link the remesher).

#include <vector>

#include <Eigen/LU>

#include "sim/collide/surface_bvh.h"
#include "sim/core/types.h"
#include "sim/tools/force_model.h"
#include "sim/tools/swept_tool_motion.h"
#include "sim/tools/tool_contact_response.h"

namespace incise::sim::tools {

struct ProbeSettings {
  Real radius = 0.004;                // tip radius [m], > 0
  Real coupling_stiffness = 500;      // k_v [N/m], > 0
  Real allowed_penetration = 0.0005;  // per step [m], in (0, radius)
  // The contacts' stiffness k_c over the coupling's k_v, > 0: stiff, so that the hand feels the
  // coupling and the tissue, not the contact (the implicit solve keeps any value stable).
  Real contact_stiffness_ratio = 20;
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
  // internal forces included: the balance predicts where the nodes go) and updates the force
  // models.
  //   x, v            #nodes by 3 positions [m] and velocities [m/s]
  //   masses          #nodes lumped [kg] (a triangle with a massless node takes no contact)
  //   inverse_masses  #nodes, what the integrator moves the nodes with (0 for a held node), for
  //                   the balance; null: 1 / masses
  // Allocates only while the number of contacts grows past what it has seen.
  // Throws std::invalid_argument for a non-finite device position or mismatched arrays.
  void step(const Vec3& device_position, const collide::SurfaceBvh& bvh, const Points& x,
            const Points& v, const VecX& masses, Points& node_forces,
            const VecX* inverse_masses = nullptr);

  const Vec3& proxy() const { return proxy_; }
  const Vec3& device() const { return device_; }
  collide::Sphere tip() const { return {proxy_, settings_.radius}; }
  // The force on the hand [N]: what the massless proxy passes on, i.e. minus the push on the
  // tissue while it pushes; k_v (p - d) otherwise (0 in free space, where p = d).
  const Vec3& hand_force() const { return hand_force_; }
  // The proxy's contacts at the last step, as ToolContactResponse found them at p0 (their penalty
  // forces are not applied: the balance's are, see the header).
  const ToolReaction& reaction() const { return response_.reaction(); }
  // The force the proxy passed on to the tissue at the last step [N].
  const Vec3& transmitted_force() const { return transmitted_; }
  const std::vector<ContactForce>& contacts() const { return response_.contacts(); }
  // What the station agent renders: the model at the device position (see the header).
  const LocalForceModel& hand_force_model() const { return hand_model_; }
  // Whether the last step's motion was stopped by the surface.
  bool blocked() const { return blocked_; }
  // Times the proxy slipped out to the device: enclosed by the tissue (inside it, or between faces
  // facing each other) and pulled on at max_force for kTrappedSteps steps, or pulled back along
  // its shaft (set_shaft) at max_force for kWithdrawnTime, from a device outside the tissue.
  int slips() const { return slips_; }
  // The direction from the tip back along the tool's shaft to the hand (normalised here), or zero
  // for a bare tip (the default). A tip the hand pulls back along its shaft cannot be held by the
  // tissue: tissue in its way has closed over the shaft, which the proxy does not model (a scope
  // pulled out of the knee stayed behind a meniscus at 4 N for good). A pull within kShaftCone of
  // it, saturated at every step for kWithdrawnTime (time, not steps: the knee's step is a sixth of
  // the liver's), from a device outside the tissue, slips the proxy free.
  // Throws std::invalid_argument for a non-finite direction.
  void set_shaft(const Vec3& towards_hand);
  static constexpr Real kShaftCone = 0.5;       // cos 60 degrees
  static constexpr Real kWithdrawnTime = 0.02;  // [s]
  static constexpr int kTrappedSteps = 100;

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
  std::vector<Vec3> corrections_;
  int saturated_steps_ = 0;
  Real withdrawn_time_ = 0;  // saturated and withdrawn at every step since [s]
  int slips_ = 0;
  Vec3 shaft_ = Vec3::Zero();  // unit, or zero: no shaft
  // Whether the hand pulls the proxy back along its shaft (within kShaftCone).
  bool withdrawn() const;
  // Active-set passes of the balance (a contact pulling would be adhesion: it leaves).
  static constexpr int kBalancePasses = 6;
  // Step 2 above on the contacts of response_ at proxy_ (p0): moves proxy_ to p, fills
  // multipliers_ (lambda per contact, 0 for the ones that left) and returns K_h's M.
  Mat3 balance(const collide::SurfaceBvh& bvh, const Points& x, const Points& v, const VecX& masses,
               const VecX* inverse_masses, const Points& other_forces);
  // Whether p lies inside the closed surface (the parity of the surface's crossings by a ray).
  bool inside(const collide::SurfaceBvh& bvh, const Points& x, const Vec3& p);
  // Whether the proxy is inside the tissue or touches faces that face each other (more than 120
  // degrees apart: a flap or a shut crack over it).
  bool enclosed(const collide::SurfaceBvh& bvh, const Points& x, const Points& v,
                const VecX& masses);
  std::vector<int> ray_triangles_;

  LocalForceModel hand_model_;
  Vec3 transmitted_ = Vec3::Zero();
  Vec3 hand_force_ = Vec3::Zero();
  bool blocked_ = false;
  // Scratch of the balance, per contact (resized, not reallocated, while the count is steady).
  std::vector<Real> multipliers_;
  std::vector<char> active_;
  // balance()'s work arrays, kept so that a step with as many contacts as the last allocates
  // nothing.
  Eigen::MatrixXd gram_, system_;
  Eigen::VectorXd excess_, ke_, a_ke_, lambda_;
  Eigen::Matrix<Real, Eigen::Dynamic, 3> normals_, kn_, a_kn_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace incise::sim::tools
