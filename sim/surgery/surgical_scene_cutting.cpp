// A surgical scene's scalpel step: the blade's cut through the tissue, and the slivers its
// stroke left collapsed once the stroke ends.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <vector>

#include "sim/surgery/surgical_scene.h"
#include "sim/surgery/surgical_scene_tool.h"

namespace incise::sim::surgery {

void SurgicalScene::cut(Tool& tool, int index) {
  TetMesh& mesh = tissue_->mesh();
  const Vec3 a = tool.tip;
  const Vec3 b = tool.tip - tool.spec.blade_length * tool.direction;
  std::vector<int> near;
  tissue_->bvh().overlapping_triangles(mesh.x, collide::Capsule{a, b, 1e-4}, near);
  if (!tool.stroke && near.empty()) return;
  // A blade reaching the condensed far field (which cannot change) ends its stroke there.
  const bool outside = far_guard_ > 0 && blade_outside_region(a, b);
  if (outside) ++cuts_outside_region_;
  if (!tool.stroke && outside) return;
  // The blade cuts the material it passes through: the cutter maps it into the rest
  // configuration through the tet its tip is in, so tissue moving under the blade is not cut
  // again (progressive_cutter.h). Where that tet is squashed or inverted, or any tet near the
  // blade is inverted (a violent push has tangled the tissue there), the blade has no place in
  // the material: the cut waits until the tissue has recovered, and says so (cuts_refused).
  if (!tool.cutter) {
    tool.cutter = std::make_unique<cut::ProgressiveCutter>(mesh, cut::CutOptions{}, 0,
                                                           cut::BladeSpace::material);
  }
  int tets_before = mesh.num_tets();
  std::vector<int> changed;
  Triangles committed;
  std::vector<int> labels;
  if (outside) {
    tool.stroke = false;
    tool.cut_waiting = false;
  } else {
    const cut::FrameReport& report = tool.cutter->update(a, b);
    tets_before = report.tets_before;
    changed = report.changed_tets;
    committed = report.committed_crack_face_nodes;
    labels = report.committed_crack_face_labels;
    tool.cut_waiting = report.blade_unmapped;
    if (report.blade_unmapped && !near.empty()) ++cuts_refused_;
    tool.stroke = !near.empty() || report.front_tets > 0;
    if (report.committed_new_tets > 0 || report.committed_crack_faces > 0) {
      for (const int s : changed) {
        if (s < tool.cutter->committed_tets()) tool.stroke_slots.push_back(s);
      }
    }
  }
  if (!tool.stroke) {
    // The blade has left the tissue: its temporary pieces go, and the tets along the path of its
    // tip keep the crack the stroke left in them (a cut shallower than the tets opens too).
    const int before = mesh.num_tets();
    const cut::FrameReport& end = tool.cutter->end_stroke(true);
    changed.insert(changed.end(), end.changed_tets.begin(), end.changed_tets.end());
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    changed.erase(std::lower_bound(changed.begin(), changed.end(), mesh.num_tets()), changed.end());
    if (end.committed_crack_faces > 0) {
      const Eigen::Index rows = committed.rows();
      committed.conservativeResize(rows + end.committed_crack_face_nodes.rows(), 3);
      committed.bottomRows(end.committed_crack_face_nodes.rows()) = end.committed_crack_face_nodes;
      labels.insert(labels.end(), end.committed_crack_face_labels.begin(),
                    end.committed_crack_face_labels.end());
      tool.stroke_slots.insert(tool.stroke_slots.end(), end.changed_tets.begin(),
                               end.changed_tets.end());
    }
    if (mesh.num_tets() != before || !changed.empty()) after_topology_change(tets_before, changed);
  } else if (!changed.empty() || mesh.num_tets() != tets_before) {
    after_topology_change(tets_before, changed);
  }
  if (committed.rows() > 0) {
    // Recorded with the labels the cutter found: some of these faces are already split by the
    // blade's temporary pieces, so no tet holds them now.
    const tools::CutDamage cut = damage_->record_cut(mesh.rest, committed, labels);
    char text[96];
    std::snprintf(text, sizeof text, "%.1f mm^2, %.1f mm^2 off target", 1e6 * cut.area,
                  1e6 * cut.area_outside_target);
    event(EventKind::cut, index, text);
    if (cut.never_event) event(EventKind::never_event, index, "a protected tissue was cut");
  }
  if (!tool.stroke) simplify_after_stroke(tool);
}

void SurgicalScene::simplify_after_stroke(Tool& tool) {
  std::vector<int> region;
  region.swap(tool.stroke_slots);
  if (region.empty()) return;
  // Node and slot numbers change: wait while another stroke is open or a grasper holds (their
  // indices would go stale); the slivers stay until the next stroke ends.
  for (const Tool& other : tools_) {
    if (other.stroke) return;
    if (other.grasper && (other.grasper->phase() == tools::GraspPhase::holding ||
                          other.grasper->phase() == tools::GraspPhase::closing)) {
      return;
    }
  }
  std::sort(region.begin(), region.end());
  region.erase(std::unique(region.begin(), region.end()), region.end());
  region.erase(std::lower_bound(region.begin(), region.end(), tissue_->mesh().num_tets()),
               region.end());
  const int slots_before = std::max(damage_->num_slots(), tissue_->mesh().num_tets());
  const cut::SimplifyReport report = tissue_->simplify(region, spec_.simplify);
  collapses_ += report.collapses;
  if (report.collapses == 0) return;
  after_compaction(report.tet_map, slots_before);
}

}  // namespace incise::sim::surgery
