// A surgical scene's adaptivity (AdaptivitySpec): the tissue refined around touching probes and
// closing graspers, and coarsened again where no tool has been for a while.
#include <algorithm>
#include <vector>

#include "sim/surgery/surgical_scene.h"
#include "sim/surgery/surgical_scene_tool.h"

namespace incise::sim::surgery {

AdaptivitySpec shed_adaptivity(const AdaptivitySpec& spec, int level) {
  AdaptivitySpec shed = spec;
  if (level >= 1) shed.max_splits = 0;
  if (level >= 2) shed.coarsen_after = 0;
  return shed;
}

void SurgicalScene::set_shed_level(int level) {
  shed_level_ = std::clamp(level, 0, kMaxAdaptivityShedLevel);
}

void SurgicalScene::adapt() {
  const AdaptivitySpec a = shed_adaptivity(spec_.adaptivity, shed_level_);
  for (const Tool& t : tools_) {
    if (t.stroke) return;  // the cutter's temporary nodes would go stale
  }
  const TetMesh& mesh = tissue_->mesh();
  bool hold_off = false;  // no coarsening now: a grasper holds or closes, a probe touches
  for (std::size_t k = 0; k < tools_.size(); ++k) {
    Tool& tool = tools_[k];
    if (!tool.has_input) continue;
    const int index = static_cast<int>(k);
    if (tool.spec.kind == ToolKind::probe && tool.probe) {
      // Where the probe touched at the last step: refined once, kept while it touches nearby.
      const tools::ContactRegion touch = tool.probe->contact_region(mesh.rest);
      if (!touch.touching) continue;
      bool known = false;
      for (Region& r : regions_) {
        if (r.tool == index && (r.centre - touch.centre).norm() < 0.5 * r.radius) {
          r.last_used = time_;
          known = true;
        }
      }
      if (!known) refine(index, touch.centre, std::max(a.radius, touch.radius + a.edge_length));
    } else if (tool.grasper) {
      const tools::GraspPhase phase = tool.grasper->phase();
      if (phase == tools::GraspPhase::closing) {
        hold_off = true;
        std::vector<int> candidates;
        const int stable = stable_nodes();
        for (const int v : surface_nodes_) {
          if (v < stable) candidates.push_back(v);
        }
        if (const auto request = tool.grasper->refine_request(
                mesh.rest, mesh.x, tissue_->inverse_masses(), candidates)) {
          refine(index, request->centre, request->radius + a.edge_length);
        }
      } else if (phase == tools::GraspPhase::holding) {
        hold_off = true;
        for (Region& r : regions_) {
          if (r.tool == index) r.last_used = time_;
        }
      }
    }
  }
  // Coarsening renumbers nodes: not while a grasper holds (or is about to). Nor while a probe or
  // scope touches the tissue: undoing a split moves the surface (a displaced midpoint's triangles
  // become the flat coarse one), which can close over a tip resting in a dimple and trap it
  // inside (liver seeds 184 and 209 ended with the probe's proxy inside the organ).
  for (const Tool& t : tools_) {
    if (t.probe && !t.probe->contacts().empty()) hold_off = true;
  }
  if (hold_off) return;
  // Regions expire even where nothing was split (the knee refuses most splits): they would pile
  // up, and a known region is never refined again.
  const auto expired = std::erase_if(
      regions_, [&](const Region& r) { return time_ - r.last_used > a.coarsen_after; });
  if (expired > 0 && !tissue_->bisections().empty()) coarsen();
}

void SurgicalScene::refine(int tool, const Vec3& centre, Real radius) {
  const AdaptivitySpec a = shed_adaptivity(spec_.adaptivity, shed_level_);
  // Refinement paused (shed_adaptivity): no region either, so that a touch that began while
  // paused is refined once the pause ends (a known region is never refined again).
  if (a.max_splits == 0) return;
  regions_.push_back({centre, radius, time_, tool});
  const BisectionReport report = tissue_->refine(centre, radius, a.edge_length, a.max_splits);
  splits_ += report.splits;
  splits_refused_ += report.refused;
  if (report.splits == 0) return;
  for (Tool& t : tools_)
    t.cutter.reset();  // its node and tet counts are stale; none has an open stroke
  update_damage(report.tets_before, report.changed, report.parents);
  follow_node_count();
}

void SurgicalScene::coarsen() {
  const Real margin = spec_.adaptivity.edge_length;
  const auto keep = [&](const Vec3& rest) {
    for (const Region& r : regions_) {
      if ((rest - r.centre).norm() <= r.radius + margin) return true;
    }
    return false;
  };
  bool any = false;
  const TetMesh& mesh = tissue_->mesh();
  for (const Bisection& s : tissue_->bisections()) {
    if (!keep(row3(mesh.rest, s.mid))) {
      any = true;
      break;
    }
  }
  if (!any) return;
  const int slots_before = std::max(damage_->num_slots(), mesh.num_tets());
  const CoarsenReport report = tissue_->coarsen(keep);
  splits_undone_ += report.undone;
  if (report.undone > 0) after_compaction(report.tet_map, slots_before);
}

}  // namespace incise::sim::surgery
