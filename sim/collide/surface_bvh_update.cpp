// Local updates of SurfaceBvh when a cut or a remesh adds or removes surface triangles. Both keep
// the layout invariant that a parent is stored before its children (refit's backward sweep
// relies on it), which is why an insertion pairs the new triangle with a leaf, never with an
// internal node: the leaf's slot becomes the new parent, and the old leaf and the new one are
// appended after it.

#include <algorithm>
#include <stdexcept>
#include <string>

#include "sim/collide/surface_bvh.h"

namespace incise::sim::collide {

namespace {

Real surface_area(const Box3& box) {
  if (box.isEmpty()) return 0;
  const Vec3 s = box.sizes();
  return 2 * (s.x() * s.y() + s.y() * s.z() + s.z() * s.x());
}

}  // namespace

int SurfaceBvh::new_node() {
  box_.emplace_back();
  left_.push_back(-1);
  right_.push_back(-1);
  parent_.push_back(-1);
  leaf_slot_.push_back(-1);
  return static_cast<int>(box_.size()) - 1;
}

void SurfaceBvh::refit_ancestors(int node) {
  for (; node >= 0; node = parent_[node]) {
    box_[node] = box_[left_[node]].merged(box_[right_[node]]);
  }
}

int SurfaceBvh::add_triangle(const Points& points, const Vec3i& triangle) {
  check_triangle(points, triangle, "SurfaceBvh::add_triangle", num_slots());
  refit_ratio_ = -1;
  const int slot = num_slots();
  triangles_.push_back(triangle);
  leaf_of_.push_back(-1);
  max_index_ = std::max(max_index_, triangle.maxCoeff());
  ++live_;
  const Box3 box = triangle_box(points, slot);

  if (live_ == 1) {  // an empty tree: the new leaf is the root
    box_.clear();
    left_.clear();
    right_.clear();
    parent_.clear();
    leaf_slot_.clear();
    free_nodes_ = 0;
    const int root = new_node();
    leaf_slot_[root] = slot;
    box_[root] = box;
    leaf_of_[slot] = root;
    return slot;
  }

  // Descend to the leaf whose subtree's box grows least when it takes the new one (the growth
  // of surface area is what makes later queries visit more nodes).
  int node = 0;
  while (left_[node] >= 0) {
    const int l = left_[node];
    const int r = right_[node];
    const Real grow_left = surface_area(box_[l].merged(box)) - surface_area(box_[l]);
    const Real grow_right = surface_area(box_[r].merged(box)) - surface_area(box_[r]);
    node = grow_left <= grow_right ? l : r;
  }
  // The leaf's node becomes the parent of (the old leaf moved to a new node, the new leaf).
  const int moved = new_node();
  const int leaf = new_node();
  const int old_slot = leaf_slot_[node];
  leaf_slot_[moved] = old_slot;
  box_[moved] = box_[node];
  parent_[moved] = node;
  leaf_of_[old_slot] = moved;
  leaf_slot_[leaf] = slot;
  box_[leaf] = box;
  parent_[leaf] = node;
  leaf_of_[slot] = leaf;
  leaf_slot_[node] = -1;
  left_[node] = moved;
  right_[node] = leaf;
  refit_ancestors(node);
  return slot;
}

void SurfaceBvh::remove_triangle(int slot) {
  if (slot < 0 || slot >= num_slots() || leaf_of_[slot] < 0) {
    throw std::invalid_argument("SurfaceBvh::remove_triangle: slot " + std::to_string(slot) +
                                (slot < 0 || slot >= num_slots()
                                     ? " is outside [0, " + std::to_string(num_slots()) + ")"
                                     : " is already removed"));
  }
  refit_ratio_ = -1;
  const int leaf = leaf_of_[slot];
  leaf_of_[slot] = -1;
  --live_;
  const auto free_node = [&](int node) {
    box_[node].setEmpty();
    left_[node] = right_[node] = parent_[node] = leaf_slot_[node] = -1;
    ++free_nodes_;
  };
  if (leaf == 0) {  // the last triangle was the root
    free_node(0);
    return;
  }
  // The sibling takes the parent's node. Its children (if any) are stored after it, hence after
  // the parent too: the parent-first order holds.
  const int parent = parent_[leaf];
  const int sibling = left_[parent] == leaf ? right_[parent] : left_[parent];
  box_[parent] = box_[sibling];
  left_[parent] = left_[sibling];
  right_[parent] = right_[sibling];
  leaf_slot_[parent] = leaf_slot_[sibling];
  if (left_[sibling] >= 0) {
    parent_[left_[sibling]] = parent;
    parent_[right_[sibling]] = parent;
  } else {
    leaf_of_[leaf_slot_[sibling]] = parent;
  }
  free_node(leaf);
  free_node(sibling);
  refit_ancestors(parent_[parent]);
}

}  // namespace incise::sim::collide
