// A surgical scene's bones against each tool: a penalty on the tool's tip and shaft, and the
// depths the damage tracker counts as contacts with protected structures.
#include <algorithm>
#include <vector>

#include "sim/surgery/surgical_scene.h"
#include "sim/surgery/surgical_scene_tool.h"

namespace incise::sim::surgery {
namespace {

// The deepest contact of a list, or nullptr.
const collide::Contact* deepest(const std::vector<collide::Contact>& contacts) {
  const collide::Contact* best = nullptr;
  for (const collide::Contact& c : contacts) {
    if (best == nullptr || c.depth > best->depth) best = &c;
  }
  return best;
}

}  // namespace

void SurgicalScene::bones(Tool& tool, int /*index*/) {
  tool.bone = {};
  tool.bone.reference_position = tool.tip;
  tool.touching_bone = false;
  if (bones_->empty()) return;
  const Real tip_radius =
      tool.spec.kind == ToolKind::probe ? tool.spec.probe.radius : tool.spec.shaft_radius;
  const collide::Sphere tip{tool.tip, tip_radius};
  const collide::Capsule shaft{tool.tip - tool.spec.shaft_length * tool.direction, tool.tip,
                               tool.spec.shaft_radius};
  std::vector<collide::Contact>& contacts = tool.bone_contacts;
  for (std::size_t b = 0; b < bones_->size(); ++b) {
    for (int shape = 0; shape < 2; ++shape) {
      contacts.clear();
      if (shape == 0) {
        (*bones_)[b].contacts(tip, contacts);
      } else {
        (*bones_)[b].contacts(shaft, contacts);
      }
      const collide::Contact* c = deepest(contacts);
      if (c == nullptr || !(c->depth > 0)) continue;
      // A penalty on the tool along the bone's normal; K = k n n^T (PSD).
      tool.bone.force += spec_.bone_stiffness * c->depth * c->normal;
      tool.bone.stiffness += spec_.bone_stiffness * c->normal * c->normal.transpose();
      tool.touching_bone = true;
      bone_depths_[b] = std::max(bone_depths_[b], c->depth);
    }
  }
}

}  // namespace incise::sim::surgery
