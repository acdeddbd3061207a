#pragma once

// A bounding-volume hierarchy (axis-aligned boxes) over the triangles of a deforming surface,
// for tool contacts with soft tissue (the AABB tree of Knee Arthroscopy VR, section VIII). Built
// once, refitted every step
// (the tree's shape is kept, only its boxes follow the motion), updated locally when cutting or
// remeshing adds or removes triangles, and rebuilt fully only when it has grown loose.
//
// Positions are not stored: every call takes `points` (#points by 3 [m]), the array the
// triangles index. It may be a TetMesh's x with the boundary faces mapped to mesh node indices,
// or a surface's own vertex array (surface_vertices); either way queries must get the same
// positions as the last build/refit/add (the boxes are those of these positions).
//
// Triangles live in slots: build gives triangle k of its input slot k, add_triangle appends a
// slot, remove_triangle kills one; slot numbers never change (contacts report them) until the
// next build(). rebuild() keeps them.
//
// Layout: one leaf per triangle, nodes in flat arrays (structure of arrays, no per-node heap
// allocation), node 0 the root, and every parent stored before its children, so that refit is
// one backward sweep. Queries walk the tree without a stack (they climb back up through the
// parent links), so they allocate nothing and are safe to run concurrently on a const tree.
//
// Costs (n live triangles): build / rebuild O(n log n) (median split on the longest axis of the
// triangle centroids); refit O(n), no allocation; add_triangle O(depth) (descends to the leaf
// whose box grows least and pairs with it); remove_triangle O(depth) (the sibling takes the
// parent's place); looseness O(n); a query O(log n + k) for k triangles near the tool on a
// well-shaped tree.

#include <vector>

#include "sim/collide/contact.h"
#include "sim/collide/tool_shapes.h"
#include "sim/core/types.h"

namespace incise::sim::collide {

// The first contact of a moving sphere with the surface.
struct SweepHit {
  Real time = 0;                    // in [0, 1]: the centre is c0 + time (c1 - c0)
  int triangle = -1;                // slot of the triangle hit
  Vec3 barycentric = Vec3::Zero();  // the touched point of that triangle
  Vec3 point = Vec3::Zero();        // the touched point [m]
  Vec3 normal = Vec3::Zero();       // unit, from the touched point to the centre at `time`
};

class SurfaceBvh {
 public:
  // Default looseness above which needs_rebuild() says so (see looseness()).
  static constexpr Real kDefaultLooseness = 1.5;

  // A tree over triangles (#T by 3 indices into points). Clears all previous slots.
  // Throws std::invalid_argument for an index outside [0, #points) or a non-finite position
  // used by a triangle.
  void build(const Points& points, const Triangles& triangles);

  // A fresh tree over the live slots (their numbers unchanged) at points; resets looseness to 1.
  void rebuild(const Points& points);

  // New boxes for moved points, bottom-up; same tree. Allocates nothing. Positions are not
  // checked here (it runs every step): keep them finite.
  // Throws std::invalid_argument if points has fewer rows than the triangles index.
  void refit(const Points& points);

  // How much worse the tree is than when it was built: (sum of the surface areas of the
  // internal boxes / the root's area) now, over the same ratio at the last build. 1 after a
  // build; it grows when triangles that were near each other move apart (the boxes of a
  // subtree swell and overlap) or when local updates pile up. Scale-free: a uniform scaling or
  // a rigid translation of the whole surface leaves it at 1. O(n).
  Real looseness() const;

  // looseness() > threshold, or over half the node slots are free after removals.
  bool needs_rebuild(Real threshold = kDefaultLooseness) const;

  // Adds triangle (three indices into points) as a new slot, inserted next to the leaf whose
  // box grows least along the descent, and returns its slot. Boxes on the path are updated from
  // points (which must hold the positions of the last refit for the other triangles).
  // Throws std::invalid_argument for an index outside [0, #points).
  int add_triangle(const Points& points, const Vec3i& triangle);

  // Kills slot `slot`: its leaf is unlinked (the sibling takes the parent's place) and the boxes
  // above shrink. Throws std::invalid_argument if slot is out of range or already dead.
  void remove_triangle(int slot);

  int num_live_triangles() const { return live_; }
  int num_slots() const { return static_cast<int>(triangles_.size()); }
  bool is_live(int slot) const { return leaf_of_[slot] >= 0; }
  const Vec3i& triangle(int slot) const { return triangles_[slot]; }
  // Number of node slots in use (2 n - 1 for n live triangles).
  int num_nodes() const { return static_cast<int>(box_.size()) - free_nodes_; }

  // The live triangles the shape touches or overlaps (closest distance <= radius), in tree
  // order, into `slots` (cleared first; no allocation once it has grown).
  void overlapping_triangles(const Points& points, const Sphere& sphere,
                             std::vector<int>& slots) const;
  void overlapping_triangles(const Points& points, const Capsule& capsule,
                             std::vector<int>& slots) const;

  // One contact per touching triangle (see shape_triangle_contact.h for the rule: normal out of
  // the tissue towards the tool, depth > 0, point and barycentric on the triangle), in tree
  // order, into `contacts` (cleared first).
  void contacts(const Points& points, const Sphere& sphere, std::vector<Contact>& contacts) const;
  void contacts(const Points& points, const Capsule& capsule, std::vector<Contact>& contacts) const;

  // Continuous check of a sphere whose centre moves from sphere.centre (time 0) to c1 (time 1)
  // in one step: true and the earliest contact with any live triangle, either side (so a fast
  // tool cannot pass through thin tissue between two steps). Exact per triangle
  // (sweep_sphere_triangle); the tree prunes with the box around both end spheres.
  bool sweep(const Points& points, const Sphere& sphere, const Vec3& c1, SweepHit& hit) const;

 private:
  // Calls visit(slot) for every live leaf whose box satisfies overlaps(box) (stackless walk).
  template <class Overlaps, class Visit>
  void walk(Overlaps&& overlaps, Visit&& visit) const;
  Box3 triangle_box(const Points& points, int slot) const;
  int build_range(const Points& points, std::vector<int>& slots, std::vector<Vec3>& centroids,
                  int first, int last, int parent);
  void refit_ancestors(int node);
  void check_points(const Points& points, const char* where) const;
  void check_triangle(const Points& points, const Vec3i& triangle, const char* where,
                      int row) const;
  Real internal_area_ratio() const;
  int new_node();

  // Nodes. left_ == -1 for a leaf (then leaf_slot_ >= 0) or a free node (leaf_slot_ == -1).
  std::vector<Box3> box_;
  std::vector<int> left_;
  std::vector<int> right_;
  std::vector<int> parent_;  // -1 for the root
  std::vector<int> leaf_slot_;
  int free_nodes_ = 0;

  // Triangle slots.
  std::vector<Vec3i> triangles_;
  std::vector<int> leaf_of_;  // the leaf node of each slot, -1 when dead
  int live_ = 0;
  int max_index_ = -1;  // the largest point index any slot uses

  Real built_ratio_ = 0;  // internal_area_ratio() at the last build
  // internal_area_ratio() as the last build or refit left it; < 0 once a triangle was added or
  // removed since.
  Real refit_ratio_ = -1;
};

}  // namespace incise::sim::collide
