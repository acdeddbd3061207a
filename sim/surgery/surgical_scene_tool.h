#pragma once
// Internal to SurgicalScene (sim/surgery/surgical_scene*.cpp): the state it keeps per tool.

#include <memory>
#include <optional>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/surgery/surgical_scene.h"

namespace incise::sim::surgery {

struct SurgicalScene::Tool {
  ToolSpec spec;
  bool has_input = false;
  ToolInput input;
  Vec3 tip = Vec3::Zero();
  Vec3 previous_tip = Vec3::Zero();  // at the step before (the tip's motion over the step)
  // Scalpel: the blade's last non-zero velocity and when it was seen [m/s, s]. Device states come
  // in gaps (the station's deadband holds back small moves): between two, the tip stands still
  // for a few steps, and a resistance that followed that would flicker on and off (a buzz in the
  // hand, a flood of contact events in the review). It is held for kBladeVelocityHoldS
  // (surgical_scene_cutting_resistance.cpp).
  Vec3 blade_velocity = Vec3::Zero();
  Real blade_velocity_time = 0;
  Mat3 rotation = Mat3::Identity();
  Vec3 direction = Vec3::UnitZ();
  // Probe and scope: made at the first input with the tip clear of the tissue, its centre outside
  // it and no deeper in it than allowed_penetration (touching is clear). A tip that first appears
  // deeper (an instrument held in the tissue as the session starts) waits until it comes out: a
  // proxy made inside would be engulfed, its contacts found from behind, and it would hold the
  // hand at up to the coupling's full force once the hand drew back; one made half in would be
  // thrown out onto the surface, a kick in the hand.
  std::optional<tools::Probe> probe;
  std::vector<int> ray_triangles;  // scratch of the entry check
  std::optional<tools::Grasper> grasper;
  ClonePtr<cut::ProgressiveCutter> cutter;  // a copy still cuts the original's mesh: rebind it
  bool stroke = false;                      // the scalpel's blade is in the tissue
  // The scalpel's last frame had no place in the material (a tangle at the blade): the cut waits
  // for the recovery, so the blade does not keep the recovery off as a working tool would.
  bool cut_waiting = false;
  std::vector<int> stroke_slots;  // committed slots the open stroke's complete cuts changed
  tools::BladeInTissue blade;     // the scalpel's blade in the tissue this step
  tools::LocalForceModel bone;    // this step's bone contacts, on the tool at its tip
  bool touching_bone = false;
  std::vector<collide::Contact> bone_contacts;  // the bone queries' scratch, kept between steps
  Vec3 hand_force = Vec3::Zero();               // grasper: the tissue's pull on the hand
  // Scalpel: the tissue's resistance to the cut this step, on the tool [N].
  Vec3 cutting_force = Vec3::Zero();
};

}  // namespace incise::sim::surgery
