// A surgical scene's scalpel against the hand: while its stroke is open, the tissue resists the
// cut with its toughness times the blade's depth in it (tools/cutting_resistance.h), on the tool.
//
// Only the tool feels it. The tissue does not get the reaction: the scene's scalpel puts no force
// on the tissue at all (its blade passes through, and the cutter parts what it passes), and the
// reaction acts at the crack front, the tets the blade is in, which the cutter keeps to itself
// and updates only every cut_every steps. Spread instead over the few surface nodes where the
// blade enters, the 1.2 N of a 6 mm deep cut would drag the liver's 4 kPa surface there by
// centimetres (a patch of radius a on a half-space holds back 8 G a / (2 - nu) sideways: 36 N/m
// for a = 5 mm), pulling the marked line away from the blade.
#include <algorithm>
#include <vector>

#include "sim/surgery/surgical_scene.h"
#include "sim/surgery/surgical_scene_tool.h"

namespace incise::sim::surgery {

namespace {
// Longer than the longest gap between a station's device states (the agent's deadband sends one
// at least every 50 ms: devices/agent/haptic_loop.h), short beside a hand coming to rest.
constexpr Real kBladeVelocityHoldS = 0.06;
// Below this the tip stands still [m/s] (a hundredth of the resistance's ramp speed).
constexpr Real kStandingSpeed = 1e-4;
}  // namespace

Real SurgicalScene::toughness(int label) const {
  for (const LabelToughness& t : spec_.toughness) {
    if (t.label == label) return t.toughness;
  }
  return spec_.default_toughness;
}

void SurgicalScene::resist_cut(Tool& tool) {
  tool.cutting_force.setZero();
  tool.blade.depth = 0;
  tool.blade.stretches.clear();
  if (!tool.stroke) return;
  const Real length = tool.spec.blade_length;
  // Beyond the blade, the rest of the shaft says whether a blade crossing no face is in or out.
  // The crack this stroke is opening runs along the blade, snapped to nodes by up to 5% of an
  // edge (cut::CutOptions) and its two sides triangulated differently: where they do not quite
  // meet, the blade crosses slivers of gap (0.3 mm of a 10 mm deep cut in 10 mm cells). Gaps under
  // a tenth of the blade are bridged; separate structures lie further apart.
  tools::blade_in_tissue(tissue_->bvh(), tissue_->mesh().x, tool.tip, tool.direction, length,
                         std::max(Real(0), tool.spec.shaft_length - length), 0.1 * length,
                         tool.blade);
  if (tool.blade.depth == 0) return;
  // Each stretch resists with its own tissue's toughness: the label of the tet behind its face.
  const std::vector<int>& face_tets = tissue_->surface().tets;
  const Eigen::VectorXi& labels = tissue_->mesh().labels;
  Real resistance = 0;  // sum of toughness x length [N]
  for (const tools::BladeStretch& s : tool.blade.stretches) {
    const int tet = face_tets[static_cast<std::size_t>(s.face)];
    resistance += toughness(labels(tet)) * (s.to - s.from);
  }
  // The velocity of the last step that moved, for up to kBladeVelocityHoldS
  // (surgical_scene_tool.h). Still passive: while the tip stands still the force does no work, and
  // the first step that moves again replaces it.
  // "Moved": faster than kStandingSpeed. A held input still moves the tip by round-off (the
  // engine interpolates between two equal inputs), and that must not replace the held velocity.
  const Vec3 step_velocity = (tool.tip - tool.previous_tip) / spec_.dt;
  if (step_velocity.squaredNorm() > kStandingSpeed * kStandingSpeed) {
    tool.blade_velocity = step_velocity;
    tool.blade_velocity_time = time_;
  } else if (time_ - tool.blade_velocity_time > kBladeVelocityHoldS) {
    tool.blade_velocity.setZero();
  }
  tool.cutting_force =
      tools::cutting_resistance(resistance / tool.blade.depth, tool.blade.depth,
                                tool.blade_velocity, tool.direction, spec_.cutting);
}

}  // namespace incise::sim::surgery
