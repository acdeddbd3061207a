// A surgical scene's grasper step: the jaws' pose, grabbing on closing, the held nodes
// prescribed, and the release events.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/surgery/surgical_scene.h"
#include "sim/surgery/surgical_scene_tool.h"

namespace incise::sim::surgery {

void SurgicalScene::set_jaws(Tool& tool, int index) {
  tools::JawPose pose;
  pose.pivot = tool.tip;
  pose.direction = tool.direction;
  pose.opening_normal = tool.rotation.col(0);
  pose.opening_angle = std::clamp(tool.input.jaw, 0.0, 1.0) * tool.spec.max_jaw_angle;
  if (const auto released = tool.grasper->set_jaws(pose)) {
    char text[64];
    std::snprintf(text, sizeof text, "%s, %d vertices",
                  std::string(to_string(released->reason)).c_str(), released->released_vertices);
    event(EventKind::release, index, text);
  }
}

void SurgicalScene::grasp(Tool& tool, int index) {
  tools::Grasper& grasper = *tool.grasper;
  TetMesh& mesh = tissue_->mesh();
  if (grasper.phase() == tools::GraspPhase::closing) {
    // Only committed nodes: a scalpel's temporary nodes are renumbered every cut frame.
    const int stable = stable_nodes();
    std::vector<int> candidates;
    for (const int v : surface_nodes_) {
      if (v < stable) candidates.push_back(v);
    }
    const int grabbed = grasper.grab(mesh.rest, mesh.x, tissue_->inverse_masses(), candidates);
    if (grabbed > 0) event(EventKind::grasp, index, std::to_string(grabbed) + " vertices");
  }
  if (const auto released = grasper.measure(tissue_->internal())) {
    char text[64];
    std::snprintf(text, sizeof text, "%s at %.3f N",
                  std::string(to_string(released->reason)).c_str(), released->pull.norm());
    event(EventKind::release, index, text);
  }
  tool.hand_force = -grasper.pull();
  if (grasper.phase() == tools::GraspPhase::holding) {
    grasper.prescribe(prescribed_);
    for (const int v : grasper.grabbed())
      prescribed_rows_.push_back(v);
  } else {
    tool.hand_force.setZero();
  }
}

}  // namespace incise::sim::surgery
