// The hybrid condensed model's topology changes: the operational region's tets replaced or
// added, the far field's checked unchanged, and the slots of both regions kept in step.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/models/hybrid_condensed_model.h"
#include "sim/models/hybrid_condensed_partition.h"

namespace incise::sim {
namespace {

bool tet_less(const Eigen::RowVector4i& a, const Eigen::RowVector4i& b) {
  return std::lexicographical_compare(a.data(), a.data() + 4, b.data(), b.data() + 4);
}

}  // namespace

void HybridCondensedModel::check_operational_tet(const Tets& tets, int row) const {
  for (int a = 0; a < 4; ++a) {
    const int node = tets(row, a);
    if (node >= 0 && static_cast<std::size_t>(node) < condensed_.size() &&
        condensed_[static_cast<std::size_t>(node)] != 0) {
      throw std::invalid_argument(where("operational tet ") + std::to_string(row) +
                                  " uses condensed interior node " + std::to_string(node));
    }
  }
}

void HybridCondensedModel::update_topology(const TetMesh& mesh) {
  std::vector<char> operational(static_cast<std::size_t>(mesh.num_tets()), 1);
  std::vector<char> found(static_cast<std::size_t>(far_tets_.rows()), 0);
  std::vector<Eigen::Index> order(static_cast<std::size_t>(far_tets_.rows()));
  for (std::size_t k = 0; k < order.size(); ++k)
    order[k] = static_cast<Eigen::Index>(k);
  std::sort(order.begin(), order.end(), [this](Eigen::Index a, Eigen::Index b) {
    return tet_less(far_tets_.row(a), far_tets_.row(b));
  });
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::RowVector4i key = sorted_tet(mesh.tets, t);
    const auto it = std::lower_bound(order.begin(), order.end(), key,
                                     [this](Eigen::Index a, const Eigen::RowVector4i& k) {
                                       return tet_less(far_tets_.row(a), k);
                                     });
    if (it != order.end() && far_tets_.row(*it) == key) {
      found[static_cast<std::size_t>(*it)] = 1;
      operational[static_cast<std::size_t>(t)] = 0;
    } else {
      check_operational_tet(mesh.tets, t);
    }
  }
  const auto missing = std::find(found.begin(), found.end(), 0);
  if (missing != found.end()) {
    throw std::invalid_argument(where("update_topology: far-field tet ") +
                                std::to_string(missing - found.begin()) +
                                " is missing (the condensed region is fixed)");
  }
  operational_view_ = region_mesh(mesh, operational, true);
  operational_->update_topology(operational_view_);
  slot_operational_ = operational;
  operational_slot_.assign(operational.size(), -1);
  global_slot_.clear();
  for (std::size_t t = 0; t < operational.size(); ++t) {
    if (operational[t] == 0) continue;
    operational_slot_[t] = static_cast<int>(global_slot_.size());
    global_slot_.push_back(static_cast<int>(t));
  }
  rebuild_masses();
  topology_changed();
}

void HybridCondensedModel::update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                                           std::span<const int> changed) {
  const std::size_t slots = static_cast<std::size_t>(mesh.num_tets());
  const std::size_t old_slots = slot_operational_.size();
  if (alive.size() != slots) {
    throw std::invalid_argument(where("update_elements: alive must have one entry per tet slot"));
  }
  if (slots < old_slots) {
    throw std::invalid_argument(where("update_elements: the mesh has fewer tet slots (") +
                                std::to_string(slots) + ") than the model (" +
                                std::to_string(old_slots) + ")");
  }
  for (std::size_t t = 0; t < old_slots; ++t) {
    if (slot_operational_[t] == 0 && alive[t] == 0) {
      throw std::invalid_argument(where("update_elements: far-field slot ") + std::to_string(t) +
                                  " is not alive (the condensed region is fixed)");
    }
  }
  for (const int s : changed) {
    if (s < 0 || static_cast<std::size_t>(s) >= slots) {
      throw std::invalid_argument(where("update_elements: changed slot ") + std::to_string(s) +
                                  " is out of range");
    }
    if (static_cast<std::size_t>(s) < old_slots &&
        slot_operational_[static_cast<std::size_t>(s)] == 0) {
      throw std::invalid_argument(where("update_elements: slot ") + std::to_string(s) +
                                  " is in the condensed region, which is fixed");
    }
    if (alive[static_cast<std::size_t>(s)] != 0) check_operational_tet(mesh.tets, s);
  }

  // New global slots become new operational slots, in order.
  std::vector<int> operational_slot = operational_slot_;
  std::vector<int> global_slot = global_slot_;
  operational_slot.resize(slots, -1);
  for (std::size_t t = old_slots; t < slots; ++t) {
    operational_slot[t] = static_cast<int>(global_slot.size());
    global_slot.push_back(static_cast<int>(t));
  }
  const Eigen::Index op_slots = static_cast<Eigen::Index>(global_slot.size());
  TetMesh& view = operational_view_;
  view.rest = mesh.rest;
  view.x.resize(0, 3);
  view.v.resize(0, 3);
  view.tets.conservativeResize(op_slots, 4);
  view.labels.conservativeResize(op_slots);
  std::vector<char> op_alive(static_cast<std::size_t>(op_slots), 0);
  for (Eigen::Index k = 0; k < op_slots; ++k)
    op_alive[static_cast<std::size_t>(k)] = alive[static_cast<std::size_t>(global_slot[k])];
  std::vector<int> op_changed;
  op_changed.reserve(changed.size() + (slots - old_slots));
  for (const int s : changed) {
    const int k = operational_slot[static_cast<std::size_t>(s)];
    op_changed.push_back(k);
    view.tets.row(k) = mesh.tets.row(s);
    view.labels(k) = mesh.labels.size() == 0 ? 0 : mesh.labels(s);
  }
  for (std::size_t t = old_slots; t < slots; ++t) {
    const int k = operational_slot[t];
    if (std::find(op_changed.begin(), op_changed.end(), k) == op_changed.end()) {
      op_changed.push_back(k);  // a new slot is a change even if the caller did not list it
      view.tets.row(k) = mesh.tets.row(static_cast<Eigen::Index>(t));
      view.labels(k) = mesh.labels.size() == 0 ? 0 : mesh.labels(static_cast<Eigen::Index>(t));
    }
  }
  operational_->update_elements(view, op_alive, op_changed);

  slot_operational_.resize(slots, 1);
  operational_slot_ = std::move(operational_slot);
  global_slot_ = std::move(global_slot);
  rebuild_masses();
  topology_changed();
}

bool HybridCondensedModel::soften_element(int t, Real factor) {
  if (t < 0 || static_cast<std::size_t>(t) >= slot_operational_.size()) {
    throw std::invalid_argument(where("soften_element: slot ") + std::to_string(t) +
                                " is out of range");
  }
  if (slot_operational_[static_cast<std::size_t>(t)] == 0) return false;
  return operational_->soften_element(operational_slot_[static_cast<std::size_t>(t)], factor);
}

}  // namespace incise::sim
