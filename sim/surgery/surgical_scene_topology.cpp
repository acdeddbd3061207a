// A surgical scene's bookkeeping when the tissue's tets or nodes change (cuts, collapses,
// refinement): the damage tracker's slots, the cutters, the grasped nodes, the per-node arrays.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "sim/surgery/surgical_scene.h"
#include "sim/surgery/surgical_scene_tool.h"

namespace incise::sim::surgery {

void SurgicalScene::after_compaction(std::span<const int> tet_map, int slots_before) {
  // Every cutter's numbering is stale (none has an open stroke): a new one is made at the next
  // stroke.
  for (Tool& t : tools_) {
    t.cutter.reset();
    std::vector<int> slots;
    for (const int s : t.stroke_slots) {
      const int to =
          s < static_cast<int>(tet_map.size()) ? tet_map[static_cast<std::size_t>(s)] : -1;
      if (to >= 0) slots.push_back(to);
    }
    t.stroke_slots = std::move(slots);
  }
  // The damage tracker's slots follow the compaction: a kept tet inherits its old slot's state.
  const TetMesh& mesh = tissue_->mesh();
  const int slots = std::max(slots_before, mesh.num_tets());
  TetMesh view;
  view.rest = mesh.rest;
  view.tets.resize(slots, 4);
  view.labels.resize(slots);
  damage_alive_.assign(static_cast<std::size_t>(slots), 0);
  std::vector<int> all(static_cast<std::size_t>(slots));
  std::vector<int> parents(static_cast<std::size_t>(slots), -1);
  for (int s = 0; s < slots; ++s) {
    all[static_cast<std::size_t>(s)] = s;
    const bool alive = s < mesh.num_tets();
    view.tets.row(s) = mesh.tets.row(alive ? s : 0);
    view.labels(s) = mesh.labels(alive ? s : 0);
    damage_alive_[static_cast<std::size_t>(s)] = alive ? 1 : 0;
  }
  for (std::size_t old = 0; old < tet_map.size(); ++old) {
    const int to = tet_map[old];
    if (to >= 0 && static_cast<int>(old) < damage_->num_slots()) {
      parents[static_cast<std::size_t>(to)] = static_cast<int>(old);
    }
  }
  damage_->update_elements(view, damage_alive_, all, parents);
  follow_node_count();
}

void SurgicalScene::update_damage(int tets_before, std::span<const int> changed,
                                  std::span<const int> parents) {
  const TetMesh& mesh = tissue_->mesh();
  // The damage tracker's slots never shrink: slots beyond the mesh's tets are dead.
  const int slots = std::max(damage_->num_slots(), mesh.num_tets());
  TetMesh view;
  view.rest = mesh.rest;
  view.tets.resize(slots, 4);
  view.labels.resize(slots);
  damage_alive_.assign(static_cast<std::size_t>(slots), 0);
  std::vector<std::pair<int, int>> all;  // slot, parent
  for (std::size_t k = 0; k < changed.size(); ++k) {
    all.emplace_back(changed[k], parents.empty() ? -1 : parents[k]);
  }
  for (int s = 0; s < slots; ++s) {
    if (s < mesh.num_tets()) {
      view.tets.row(s) = mesh.tets.row(s);
      view.labels(s) = mesh.labels(s);
      damage_alive_[static_cast<std::size_t>(s)] = 1;
    } else {
      view.tets.row(s) = mesh.tets.row(0);  // dead: any valid row
      view.labels(s) = mesh.labels(0);
      if (s < tets_before || s < damage_->num_slots()) all.emplace_back(s, -1);
    }
  }
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end(),
                        [](const auto& p, const auto& q) { return p.first == q.first; }),
            all.end());
  std::vector<int> slots_changed, slot_parents;
  for (const auto& [slot, parent] : all) {
    slots_changed.push_back(slot);
    slot_parents.push_back(parent < damage_->num_slots() ? parent : -1);
  }
  damage_->update_elements(view, damage_alive_, slots_changed, slot_parents);
}

void SurgicalScene::follow_node_count() {
  const int n = tissue_->mesh().num_nodes();
  prescribed_.mask = AxisMask::Zero(n, 3);
  prescribed_.position = Points::Zero(n, 3);
  prescribed_rows_.clear();
  surface_nodes_ = tissue_->surface().nodes;
}

void SurgicalScene::after_topology_change(int tets_before, std::span<const int> changed) {
  tissue_->topology_changed(tets_before, changed);
  // New pieces start undamaged: a parent search per cut frame would cost O(#changed x #tets);
  // the damage of a cut piece is the cut's own record.
  update_damage(tets_before, changed, {});
  follow_node_count();
  const TetMesh& mesh = tissue_->mesh();
  const int n = mesh.num_nodes();
  const int stable = stable_nodes();
  for (Tool& tool : tools_) {
    if (!tool.grasper) continue;
    for (const int v : std::vector<int>(tool.grasper->grabbed())) {
      if (v >= std::min(n, stable)) {
        if (const auto released = tool.grasper->on_vertex_removed(v)) {
          event(EventKind::release, static_cast<int>(&tool - tools_.data()),
                std::string(to_string(released->reason)) + " (cut away)");
        }
      }
    }
  }
}

int SurgicalScene::stable_nodes() const {
  int stable = tissue_->mesh().num_nodes();
  for (const Tool& tool : tools_) {
    if (tool.cutter) stable = std::min(stable, tool.cutter->committed_nodes());
  }
  return stable;
}

}  // namespace incise::sim::surgery
