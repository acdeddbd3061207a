#include "sim/collide/surface_bvh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/collide/shape_triangle_contact.h"
#include "sim/collide/triangle_geometry.h"

namespace incise::sim::collide {

namespace {

Real surface_area(const Box3& box) {
  if (box.isEmpty()) return 0;
  const Vec3 s = box.sizes();
  return 2 * (s.x() * s.y() + s.y() * s.z() + s.z() * s.x());
}

void check_radius(Real radius, const char* where) {
  if (!(radius >= 0) || !std::isfinite(radius)) {
    throw std::invalid_argument(std::string(where) + ": radius must be finite and >= 0, got " +
                                std::to_string(radius));
  }
}

Vec3 corner(const Points& points, const Vec3i& triangle, int k) {
  return row3(points, triangle[k]);
}

}  // namespace

// ---- Construction and refit ------------------------------------------------------------------

void SurfaceBvh::build(const Points& points, const Triangles& triangles) {
  for (int t = 0; t < triangles.rows(); ++t) {
    check_triangle(points, triangles.row(t).transpose(), "SurfaceBvh::build", t);
  }
  const int n = static_cast<int>(triangles.rows());
  triangles_.resize(n);
  max_index_ = -1;
  for (int t = 0; t < n; ++t) {
    triangles_[t] = triangles.row(t).transpose();
    max_index_ = std::max(max_index_, triangles_[t].maxCoeff());
  }
  leaf_of_.assign(n, 0);  // all live; rebuild() sets the leaves
  rebuild(points);
}

void SurfaceBvh::rebuild(const Points& points) {
  check_points(points, "SurfaceBvh::rebuild");
  std::vector<int> slots;
  slots.reserve(triangles_.size());
  std::vector<Vec3> centroids(triangles_.size());
  for (int s = 0; s < num_slots(); ++s) {
    if (leaf_of_[s] < 0) continue;
    slots.push_back(s);
    centroids[s] = (corner(points, triangles_[s], 0) + corner(points, triangles_[s], 1) +
                    corner(points, triangles_[s], 2)) /
                   3;
  }
  box_.clear();
  left_.clear();
  right_.clear();
  parent_.clear();
  leaf_slot_.clear();
  free_nodes_ = 0;
  live_ = static_cast<int>(slots.size());
  const std::size_t capacity = slots.empty() ? 0 : 2 * slots.size() - 1;
  box_.reserve(capacity);
  left_.reserve(capacity);
  right_.reserve(capacity);
  parent_.reserve(capacity);
  leaf_slot_.reserve(capacity);
  if (!slots.empty()) build_range(points, slots, centroids, 0, live_, -1);
  built_ratio_ = refit_ratio_ = internal_area_ratio();
}

int SurfaceBvh::build_range(const Points& points, std::vector<int>& slots,
                            std::vector<Vec3>& centroids, int first, int last, int parent) {
  const int node = new_node();
  parent_[node] = parent;
  if (last - first == 1) {
    leaf_slot_[node] = slots[first];
    leaf_of_[slots[first]] = node;
    box_[node] = triangle_box(points, slots[first]);
    return node;
  }
  // Split at the median centroid along the longest axis of the centroids' box: balanced (depth
  // log2 n), and the two halves are spatially apart.
  Box3 centroid_box;
  for (int i = first; i < last; ++i)
    centroid_box.extend(centroids[slots[i]]);
  int axis = 0;
  centroid_box.sizes().maxCoeff(&axis);
  const int middle = (first + last) / 2;
  std::nth_element(slots.begin() + first, slots.begin() + middle, slots.begin() + last,
                   [&](int s, int t) { return centroids[s][axis] < centroids[t][axis]; });
  const int left = build_range(points, slots, centroids, first, middle, node);
  const int right = build_range(points, slots, centroids, middle, last, node);
  left_[node] = left;
  right_[node] = right;
  box_[node] = box_[left].merged(box_[right]);
  return node;
}

void SurfaceBvh::refit(const Points& points) {
  check_points(points, "SurfaceBvh::refit");
  // Children are stored after their parents, so a backward sweep sees them first. The internal
  // nodes' areas are summed on the way (looseness() then costs nothing).
  Real internal_area = 0;
  for (int node = static_cast<int>(box_.size()) - 1; node >= 0; --node) {
    if (left_[node] >= 0) {
      box_[node] = box_[left_[node]].merged(box_[right_[node]]);
      internal_area += surface_area(box_[node]);
    } else if (leaf_slot_[node] >= 0) {
      box_[node] = triangle_box(points, leaf_slot_[node]);
    }
  }
  const Real root_area = box_.empty() ? 0 : surface_area(box_[0]);
  refit_ratio_ = root_area > 0 ? internal_area / root_area : 0;
}

Box3 SurfaceBvh::triangle_box(const Points& points, int slot) const {
  const Vec3i& t = triangles_[slot];
  Box3 box(corner(points, t, 0));
  box.extend(corner(points, t, 1));
  box.extend(corner(points, t, 2));
  return box;
}

Real SurfaceBvh::internal_area_ratio() const {
  if (box_.empty()) return 0;
  const Real root_area = surface_area(box_[0]);
  if (!(root_area > 0)) return 0;
  Real sum = 0;
  for (std::size_t node = 0; node < box_.size(); ++node) {
    if (left_[node] >= 0) sum += surface_area(box_[node]);
  }
  return sum / root_area;
}

Real SurfaceBvh::looseness() const {
  if (!(built_ratio_ > 0)) return 1;
  return (refit_ratio_ >= 0 ? refit_ratio_ : internal_area_ratio()) / built_ratio_;
}

bool SurfaceBvh::needs_rebuild(Real threshold) const {
  return looseness() > threshold || 2 * free_nodes_ > static_cast<int>(box_.size());
}

void SurfaceBvh::check_points(const Points& points, const char* where) const {
  if (points.rows() <= max_index_) {
    throw std::invalid_argument(std::string(where) + ": points has " +
                                std::to_string(points.rows()) +
                                " rows but the triangles use index " + std::to_string(max_index_));
  }
}

void SurfaceBvh::check_triangle(const Points& points, const Vec3i& triangle, const char* where,
                                int row) const {
  for (int k = 0; k < 3; ++k) {
    const int index = triangle[k];
    if (index < 0 || index >= points.rows()) {
      throw std::invalid_argument(std::string(where) + ": triangle " + std::to_string(row) +
                                  " has index " + std::to_string(index) + " outside [0, " +
                                  std::to_string(points.rows()) + ")");
    }
    if (!points.row(index).allFinite()) {
      throw std::invalid_argument(std::string(where) + ": triangle " + std::to_string(row) +
                                  " uses point " + std::to_string(index) +
                                  " whose position is not finite");
    }
  }
}

// ---- Queries ---------------------------------------------------------------------------------

template <class Overlaps, class Visit>
void SurfaceBvh::walk(Overlaps&& overlaps, Visit&& visit) const {
  if (box_.empty() || (left_[0] < 0 && leaf_slot_[0] < 0)) return;
  // Stackless depth-first walk: coming from the parent, test the node and go down to its left
  // child; coming back from the left child, go to the right one; from the right, go up.
  int node = 0;
  int previous = -1;
  while (node >= 0) {
    const int parent = parent_[node];
    if (previous == parent) {
      if (overlaps(box_[node])) {
        if (left_[node] >= 0) {
          previous = node;
          node = left_[node];
          continue;
        }
        visit(leaf_slot_[node]);
      }
      previous = node;
      node = parent;
    } else if (previous == left_[node]) {
      previous = node;
      node = right_[node];
    } else {
      previous = node;
      node = parent;
    }
  }
}

namespace {

auto near_point(const Vec3& point, Real radius) {
  return [point, radius2 = radius * radius](const Box3& box) {
    return box.squaredExteriorDistance(point) <= radius2;
  };
}

auto overlaps_box(const Box3& query) {
  return [query](const Box3& box) { return box.intersects(query); };
}

Box3 capsule_box(const Capsule& capsule) {
  const Vec3 r = Vec3::Constant(capsule.radius);
  return Box3(capsule.a.cwiseMin(capsule.b) - r, capsule.a.cwiseMax(capsule.b) + r);
}

}  // namespace

void SurfaceBvh::overlapping_triangles(const Points& points, const Sphere& sphere,
                                       std::vector<int>& slots) const {
  check_radius(sphere.radius, "SurfaceBvh::overlapping_triangles");
  slots.clear();
  walk(near_point(sphere.centre, sphere.radius), [&](int slot) {
    const Vec3i& t = triangles_[slot];
    const Vec3 a = corner(points, t, 0), b = corner(points, t, 1), c = corner(points, t, 2);
    const Vec3 w = closest_point_barycentric(sphere.centre, a, b, c);
    if ((w[0] * a + w[1] * b + w[2] * c - sphere.centre).norm() <= sphere.radius) {
      slots.push_back(slot);
    }
  });
}

void SurfaceBvh::overlapping_triangles(const Points& points, const Capsule& capsule,
                                       std::vector<int>& slots) const {
  check_radius(capsule.radius, "SurfaceBvh::overlapping_triangles");
  slots.clear();
  walk(overlaps_box(capsule_box(capsule)), [&](int slot) {
    const Vec3i& t = triangles_[slot];
    const SegmentTriangleClosest closest = segment_triangle_closest(
        capsule.a, capsule.b, corner(points, t, 0), corner(points, t, 1), corner(points, t, 2));
    if (closest.distance <= capsule.radius) slots.push_back(slot);
  });
}

void SurfaceBvh::contacts(const Points& points, const Sphere& sphere,
                          std::vector<Contact>& contacts) const {
  check_radius(sphere.radius, "SurfaceBvh::contacts");
  contacts.clear();
  walk(near_point(sphere.centre, sphere.radius), [&](int slot) {
    const Vec3i& t = triangles_[slot];
    Contact contact;
    if (sphere_triangle_contact(sphere, corner(points, t, 0), corner(points, t, 1),
                                corner(points, t, 2), contact)) {
      contact.triangle = slot;
      contacts.push_back(contact);
    }
  });
}

void SurfaceBvh::contacts(const Points& points, const Capsule& capsule,
                          std::vector<Contact>& contacts) const {
  check_radius(capsule.radius, "SurfaceBvh::contacts");
  contacts.clear();
  walk(overlaps_box(capsule_box(capsule)), [&](int slot) {
    const Vec3i& t = triangles_[slot];
    Contact contact;
    if (capsule_triangle_contact(capsule, corner(points, t, 0), corner(points, t, 1),
                                 corner(points, t, 2), contact)) {
      contact.triangle = slot;
      contacts.push_back(contact);
    }
  });
}

bool SurfaceBvh::sweep(const Points& points, const Sphere& sphere, const Vec3& c1,
                       SweepHit& hit) const {
  check_radius(sphere.radius, "SurfaceBvh::sweep");
  const Capsule swept{sphere.centre, c1, sphere.radius};
  bool found = false;
  walk(overlaps_box(capsule_box(swept)), [&](int slot) {
    const Vec3i& t = triangles_[slot];
    SweepContact contact;
    if (!sweep_sphere_triangle(sphere.centre, c1, sphere.radius, corner(points, t, 0),
                               corner(points, t, 1), corner(points, t, 2), contact)) {
      return;
    }
    if (found && contact.time >= hit.time) return;
    found = true;
    hit.time = contact.time;
    hit.triangle = slot;
    hit.barycentric = contact.barycentric;
  });
  if (!found) return false;
  const Vec3i& t = triangles_[hit.triangle];
  const Vec3& w = hit.barycentric;
  hit.point =
      w[0] * corner(points, t, 0) + w[1] * corner(points, t, 1) + w[2] * corner(points, t, 2);
  const Vec3 offset = sphere.centre + hit.time * (c1 - sphere.centre) - hit.point;
  const Real distance = offset.norm();
  hit.normal = distance > 0 ? Vec3(offset / distance)
                            : triangle_normal(corner(points, t, 0), corner(points, t, 1),
                                              corner(points, t, 2));
  return true;
}

}  // namespace incise::sim::collide
