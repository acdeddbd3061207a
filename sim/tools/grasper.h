#pragma once

// A grasper (forceps) holding soft tissue. Paloc 2006 ("Grasping"): once the forceps are closed,
// the vertex nearest to them is constrained to the instrument; when the force on it exceeds a
// threshold the constraint is removed, and the mesh is resimplified afterwards. Fiorini et al.
// (the grabbing gesture): the masses inside a small sphere at the closure point are marked at the
// closing instant and then moved with the tool.
//
// Rules:
//   - Phases: open -> closing (the opening angle fell to settings.close_angle) -> holding (grab()
//     marked vertices) or closed_empty (grab() found none: jaws closed on air do not grab tissue
//     they are later pushed into) -> open (the angle rose to settings.open_angle).
//   - Grab region: the candidate vertices within jaw_radius + grab_margin of the triangle
//     (pivot, tip 0, tip 1): both jaw capsules and the space between them. If none is there,
//     the one candidate nearest to the tips' midpoint, if it is within settings.reach of it
//     (the nearest vertex of Paloc 2006); else nothing. Candidates are the caller's (the body's
//     surface vertices, or all of them for the masses of Fiorini et al.); vertices with inverse
//     mass 0 (fixed or dead slots) are never grabbed.
//   - Jaw frame: origin at the pivot, axes (d, u, d x u) with d the tool axis and u the opening
//     normal's part orthogonal to d. A grabbed vertex keeps its offset in that frame from the
//     grab on (no jump at the grab): it follows the tool's translation and rotation, not the
//     jaws' further closing.
//   - Holding: the grabbed vertices' positions and velocities are prescribed (prescribe() for
//     symplectic_euler_step, or hold() after any step, e.g. AdaptiveBody::step).
//   - Pull: with f the tissue's internal (elastic + damping) forces, the force the jaws exert on
//     the tissue is pull = -sum over grabbed i of f_i (quasi-static: the inertia and weight of
//     the few held vertices are left out); the hand feels -pull. Since the internal forces sum
//     to zero, pull is also the net force on the free vertices (Newton's third law).
//   - Release: when the jaws open (reason opened; phase open), when |pull| > the tear force
//     (torn) or when every grabbed vertex was removed (lost); after these two the jaws are still
//     closed on nothing (phase closed_empty) and must open before they grab again. The release
//     event carries a ball in rest coordinates around the grabbed vertices: the region to
//     resimplify (decimate), which speeds up the relaxation to rest (Paloc 2006).
//
// One step, with x, v the state it starts from:
//   set_jaws(pose at the end of the step)        -> event (opened)?
//   if phase() == closing: [refine_request, refine, recompute candidates], grab(rest, x, ...)
//   f = internal forces at (x, v); measure(f)    -> event (torn)?
//   prescribe(p) + symplectic_euler_step(..., p, f, x, v)   or   any step, then hold(dt, x, v)
//
// Works on plain arrays (a TetMesh's nodes or an AdaptiveBody's vertex slots alike): rest, x, v
// #vertices by 3, inverse masses #vertices. Vertices removed or renumbered by remeshing or cutting
// while held must be reported (on_vertex_removed, remap) before the next step.
//
// Per-step calls (set_jaws, measure, prescribe, hold) allocate nothing; grab allocates.

#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "sim/collide/tool_shapes.h"
#include "sim/core/types.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim::tools {

struct GraspSettings {
  Real jaw_length = 0.01;     // pivot to tip [m], > 0
  Real jaw_radius = 0.001;    // [m], > 0
  Real grab_margin = 0.0005;  // added to jaw_radius for the grab region [m], >= 0
  Real reach = 0.003;         // the nearest-vertex fallback grabs only within this distance of the
                              // tips' midpoint [m], >= 0 (0: no fallback)
  Real close_angle = 0.1;     // at or below this opening angle the jaws close [rad], in [0, pi)
  Real open_angle = 0.2;      // at or above it they open again [rad], in [close_angle, pi)
  Real tear_force = 1.0;      // |pull| above this tears the tissue out of the jaws [N], > 0
                              // (+infinity: never)
};

// The tool this step: the jaws as in collide::make_jaw_pair.
struct JawPose {
  Vec3 pivot = Vec3::Zero();            // the hinge [m]
  Vec3 direction = Vec3::UnitZ();       // tool axis, pivot towards the tips (any length > 0)
  Vec3 opening_normal = Vec3::UnitX();  // not parallel to direction
  Real opening_angle = 0;               // [rad], in [0, pi)
};

enum class GraspPhase { open, closing, holding, closed_empty };
enum class ReleaseReason { opened, torn, lost };

std::string_view to_string(GraspPhase phase);
std::string_view to_string(ReleaseReason reason);

// A ball in rest coordinates [m]: where to refine before a grab, or to decimate after a release
// (e.g. remesh::sphere_size_field(centre, radius, size)).
struct RestRegion {
  Vec3 centre = Vec3::Zero();
  Real radius = 0;
};

struct ReleaseEvent {
  ReleaseReason reason = ReleaseReason::opened;
  Vec3 pull = Vec3::Zero();   // the last measured pull [N]
  int released_vertices = 0;  // how many were held
  // The ball around the rest points of every vertex this grasp grabbed (its centroid, out to the
  // farthest), widened by half the jaw length + jaw_radius + grab_margin.
  RestRegion resimplify;
};

class Grasper {
 public:
  // Throws std::invalid_argument for settings out of range (the message names the field).
  explicit Grasper(GraspSettings settings = {});

  // The pose for the end of the coming step. Moves the phase by the opening angle (above) and
  // returns the release event when the jaws open on held tissue. Call once per step, first.
  // Throws std::invalid_argument as make_jaw_pair for a bad pose (the grasper is unchanged).
  std::optional<ReleaseEvent> set_jaws(const JawPose& pose);

  // In phase closing: the ball (rest coordinates) to refine before grab(). Centre: the rest point
  // under the middle of the jaws (halfway from the pivot to the tips' midpoint), taken as the
  // rest point of the candidate nearest to it shifted by its world offset (a translation-only
  // pull-back, exact for an undeformed or translated body). Radius: half the jaw length plus the
  // larger of jaw_radius + grab_margin and reach, so that the ball holds the grab region and
  // the fallback's reach around the tips.
  // Empty when there is no candidate with inverse mass > 0 or the phase is not closing.
  // Throws std::invalid_argument for wrongly sized arrays or a candidate out of range.
  std::optional<RestRegion> refine_request(const Points& rest, const Points& x,
                                           const VecX& inverse_masses,
                                           std::span<const int> candidates) const;

  // In phase closing: marks the grabbed vertices (rules above) at their positions x, the state
  // the coming step starts from, and records their offsets in the jaw frame of the previous pose
  // (the one x belongs to; the first pose if there was none) and their rest points; the phase
  // becomes holding (some grabbed) or closed_empty (none). Returns the number grabbed. Duplicate
  // candidates count once. Throws std::logic_error outside phase closing; std::invalid_argument for
  // rest, x and inverse_masses of different row counts or a candidate out of range.
  int grab(const Points& rest, const Points& x, const VecX& inverse_masses,
           std::span<const int> candidates);

  // While holding: pull = -(sum of internal_forces over the grabbed rows), the tissue's internal
  // forces at the state the coming step starts from. Releases (reason torn) when |pull| >
  // tear_force. Returns the event, if any. Without held vertices it does nothing.
  // Throws std::invalid_argument if internal_forces has too few rows.
  std::optional<ReleaseEvent> measure(const Points& internal_forces);

  // While holding: sets the mask and position rows of the grabbed vertices to the jaw frame's
  // positions for the end of the step (other rows untouched; the caller clears them). Nothing
  // otherwise. Throws std::invalid_argument if mask or position has too few rows.
  void prescribe(Prescribed& prescribed) const;

  // While holding, after a step that left the grabbed rows free: x_i = the jaw frame's position,
  // v_i = (x_i - its position at the previous pose) / dt: what a prescribed step gives.
  // Throws std::invalid_argument for dt <= 0 or too few rows.
  void hold(Real dt, Points& x, Points& v) const;

  // The body lost a vertex (decimation removed it, a cut replaced it): it is no longer held. When
  // none is left the grasp ends; the event (reason lost) is returned.
  std::optional<ReleaseEvent> on_vertex_removed(int vertex);
  // The body's vertices were renumbered: vertex i is now old_to_new[i], or gone if < 0. Returns
  // the event if none is left. Throws std::invalid_argument if a held index is outside
  // old_to_new or two held vertices map to the same new index.
  std::optional<ReleaseEvent> remap(std::span<const int> old_to_new);

  // Tear threshold of the tissue now held [N], > 0 (e.g. by the grabbed region's tissue label).
  void set_tear_force(Real tear_force);

  GraspPhase phase() const { return phase_; }
  const GraspSettings& settings() const { return settings_; }
  // The jaws of the last pose (for contacts and rendering).
  const collide::JawPair& jaws() const { return jaws_; }
  // Grabbed vertex indices, ascending (empty unless holding).
  const std::vector<int>& grabbed() const { return grabbed_; }
  // The jaw frame's position of held vertex k (grabbed()[k]) at the current pose [m].
  Vec3 held_position(std::size_t k) const;
  // The last measured pull on the tissue [N] (0 when not holding); the hand feels -pull().
  const Vec3& pull() const { return pull_; }

 private:
  void set_frame(const JawPose& pose);
  ReleaseEvent release(ReleaseReason reason);
  void check_arrays(const Points& rest, const Points& x, const VecX& inverse_masses,
                    std::span<const int> candidates, const char* where) const;

  GraspSettings settings_;
  GraspPhase phase_ = GraspPhase::open;
  collide::JawPair jaws_;
  // Jaw frame: world = origin + rotation * offset. previous_* is the pose before the last
  // set_jaws (for hold()'s velocities).
  Vec3 origin_ = Vec3::Zero();
  Mat3 rotation_ = Mat3::Identity();
  Vec3 previous_origin_ = Vec3::Zero();
  Mat3 previous_rotation_ = Mat3::Identity();
  Vec3 tips_midpoint_ = Vec3::Zero();
  bool has_pose_ = false;
  // Held vertices (sorted by index) and their jaw-frame offsets.
  std::vector<int> grabbed_;
  std::vector<Vec3> offsets_;
  // The rest points of every vertex grabbed by this grasp (kept when a vertex is removed later,
  // so that the resimplify region still covers it).
  std::vector<Vec3> rest_points_;
  Vec3 pull_ = Vec3::Zero();
};

}  // namespace incise::sim::tools
