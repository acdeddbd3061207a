#pragma once

// No tunnelling: where a sphere tool may go this step. The tool is commanded
// from `from` (its effective centre last step) to `to`; a hand moves it by up to ~1 cm per 2 ms
// step, more than a thin membrane is thick, so a check at the end positions alone would let it
// pass through.
//
// The rule (a clamp, not sub-steps): the tool's inner core, the sphere of radius
// r - allowed_penetration, may not enter the tissue.
//  1. Push out: if the tissue has moved into the core since the last step (a stretched membrane
//     springing back, tissue pushed by something else), the tool is first moved out along the
//     deepest core contact's normal by its depth, up to four times. The tool behaves as a proxy
//     (god object) that the tissue can push back, not as a kinematic body the tissue must flow
//     around: an explicit penalty is too soft to keep a fast or tense tissue out on its own
//     (tool_contact_response.h).
//  2. Sweep: the core's motion is swept against the surface triangles (sweep_sphere_triangle,
//     exact per triangle); at the first hit whose motion goes into the touched triangle
//     (motion . n < 0, n from the touched point to the core's centre) the tool stops, and the
//     rest of the motion slides along that surface (its component into n removed), up to three
//     hits per step. Moving away or sideways is never blocked.
// So at the clamped centre the full sphere enters the tissue (as it was at the start of the
// step) by at most allowed_penetration, its centre never crosses a triangle, and the penalty
// contact at that centre pushes the tissue out of the way: the tool advances as fast as the
// tissue yields. Tolerance: after the tissue's own step the penetration is at most
// allowed_penetration plus how far a surface point moved towards the tool in that step
// (tests/sim/tools/swept_tool_motion_test.cpp measures it).
// Sub-stepping was not chosen: it costs a contact solve per sub-step and still needs a sweep for
// membranes thinner than one sub-step's travel.

#include <vector>

#include "sim/collide/surface_bvh.h"
#include "sim/core/types.h"

namespace incise::sim::tools {

struct ToolMotion {
  Vec3 centre = Vec3::Zero();  // the effective centre this step [m]
  bool blocked = false;        // the core met the surface
  int triangle = -1;           // slot of the last triangle that blocked it, or -1
  Vec3 normal = Vec3::Zero();  // that triangle's contact normal (tissue to tool), or 0
};

class SweptToolMotion {
 public:
  //   radius               the tool sphere's radius [m], > 0
  //   allowed_penetration  [m], in (0, radius): how deep the tool may enter per step
  // Throws std::invalid_argument for values out of range.
  SweptToolMotion(Real radius, Real allowed_penetration);

  // The clamped motion from `from` to `to` over the surface at x (bvh refitted to x). Allocates
  // nothing once its work arrays have grown.
  // Throws std::invalid_argument for a non-finite position.
  ToolMotion move(const collide::SurfaceBvh& bvh, const Points& x, const Vec3& from,
                  const Vec3& to);

  Real radius() const { return radius_; }
  Real allowed_penetration() const { return allowed_; }

 private:
  Real radius_;
  Real allowed_;
  std::vector<int> slots_;
  std::vector<collide::Contact> contacts_;
};

}  // namespace incise::sim::tools
