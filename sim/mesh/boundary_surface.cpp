#include "sim/mesh/boundary_surface.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "sim/mesh/tet_adjacency.h"

namespace incise::sim {

BoundarySurface boundary_surface(const TetMesh& mesh) {
  BoundarySurface surface;
  const Triangles global = boundary_faces(mesh.tets, &surface.tets);
  // Global -> local vertex numbers; -1 for nodes off the surface. Ascending local numbering keeps
  // `nodes` sorted, so the surface of the same mesh is always numbered the same way.
  std::vector<int> local(static_cast<std::size_t>(mesh.num_nodes()), -1);
  for (Eigen::Index f = 0; f < global.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      local[static_cast<std::size_t>(global(f, c))] = 0;
  }
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (local[static_cast<std::size_t>(i)] < 0) continue;
    local[static_cast<std::size_t>(i)] = static_cast<int>(surface.nodes.size());
    surface.nodes.push_back(i);
  }
  surface.faces.resize(global.rows(), 3);
  for (Eigen::Index f = 0; f < global.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      surface.faces(f, c) = local[static_cast<std::size_t>(global(f, c))];
  }
  return surface;
}

namespace {

constexpr int kKeyBits = 21;

// Face k of a tet row as its three nodes sorted, packed so that numeric order is lexicographic.
std::uint64_t face_key(const Tets& tets, int t, int k) {
  std::array<std::uint64_t, 3> n{};
  for (int c = 0; c < 3; ++c) {
    const int node = tets(t, kTetFaces[k][c]);
    if (node < 0 || node >= (1 << kKeyBits)) {
      throw std::invalid_argument("BoundaryTracker: node " + std::to_string(node) +
                                  " is outside [0, 2^21)");
    }
    n[static_cast<std::size_t>(c)] = static_cast<std::uint64_t>(node);
  }
  std::sort(n.begin(), n.end());
  return (n[0] << (2 * kKeyBits)) | (n[1] << kKeyBits) | n[2];
}

}  // namespace

BoundaryTracker::BoundaryTracker(const Tets& tets) : tets_(tets) {
  faces_.reserve(static_cast<std::size_t>(tets.rows()) * 3);
  for (int t = 0; t < static_cast<int>(tets.rows()); ++t)
    add(t);
}

void BoundaryTracker::add(int t) {
  for (int k = 0; k < 4; ++k) {
    Face& face = faces_[face_key(tets_, t, k)];
    if (face.count == 2) {
      throw std::invalid_argument("BoundaryTracker: a face of tet " + std::to_string(t) +
                                  " is shared by three tets");
    }
    if (face.count == 1) boundary_.erase({face.tet[0], face.local[0]});
    face.tet[static_cast<std::size_t>(face.count)] = t;
    face.local[static_cast<std::size_t>(face.count)] = k;
    ++face.count;
    if (face.count == 1) boundary_.insert({t, k});
  }
}

void BoundaryTracker::remove(int t) {
  for (int k = 0; k < 4; ++k) {
    const auto it = faces_.find(face_key(tets_, t, k));
    if (it == faces_.end()) continue;
    Face& face = it->second;
    const int slot = face.tet[0] == t && face.local[0] == k ? 0 : 1;
    if (face.count == 1) {
      boundary_.erase({t, k});
      faces_.erase(it);
      continue;
    }
    // The other tet keeps the face, alone now: a boundary face again.
    const int other = 1 - slot;
    face.tet[0] = face.tet[static_cast<std::size_t>(other)];
    face.local[0] = face.local[static_cast<std::size_t>(other)];
    face.tet[1] = -1;
    face.local[1] = -1;
    face.count = 1;
    boundary_.insert({face.tet[0], face.local[0]});
  }
}

void BoundaryTracker::update(const Tets& tets, std::span<const int> changed) {
  const auto old_rows = tets_.rows();
  if (tets.rows() < old_rows) {
    throw std::invalid_argument("BoundaryTracker::update: the mesh shrank (rebuild the tracker)");
  }
  for (const int t : changed) {
    if (t < old_rows) remove(t);
  }
  tets_.conservativeResize(tets.rows(), 4);
  for (const int t : changed)
    tets_.row(t) = tets.row(t);
  for (const int t : changed)
    add(t);
}

BoundarySurface BoundaryTracker::surface(int num_nodes) const {
  BoundarySurface surface;
  std::vector<int> local(static_cast<std::size_t>(num_nodes), -1);
  for (const auto& [t, k] : boundary_) {
    for (int c = 0; c < 3; ++c)
      local[static_cast<std::size_t>(tets_(t, kTetFaces[k][c]))] = 0;
  }
  for (int i = 0; i < num_nodes; ++i) {
    if (local[static_cast<std::size_t>(i)] < 0) continue;
    local[static_cast<std::size_t>(i)] = static_cast<int>(surface.nodes.size());
    surface.nodes.push_back(i);
  }
  surface.faces.resize(static_cast<Eigen::Index>(boundary_.size()), 3);
  surface.tets.reserve(boundary_.size());
  Eigen::Index f = 0;
  for (const auto& [t, k] : boundary_) {
    for (int c = 0; c < 3; ++c)
      surface.faces(f, c) = local[static_cast<std::size_t>(tets_(t, kTetFaces[k][c]))];
    surface.tets.push_back(t);
    ++f;
  }
  return surface;
}

void surface_vertices(const BoundarySurface& surface, const Points& x, Points& V, Points& N) {
  const auto count = static_cast<Eigen::Index>(surface.nodes.size());
  V.resize(count, 3);  // no-ops once sized
  N.resize(count, 3);
  for (Eigen::Index j = 0; j < count; ++j)
    V.row(j) = x.row(surface.nodes[static_cast<std::size_t>(j)]);
  N.setZero();
  for (Eigen::Index f = 0; f < surface.faces.rows(); ++f) {
    const int a = surface.faces(f, 0);
    const int b = surface.faces(f, 1);
    const int c = surface.faces(f, 2);
    // |(b - a) x (c - a)| is twice the face's area: the sum is area weighted.
    const Vec3 area = (row3(V, b) - row3(V, a)).cross(row3(V, c) - row3(V, a));
    N.row(a) += area.transpose();
    N.row(b) += area.transpose();
    N.row(c) += area.transpose();
  }
  for (Eigen::Index j = 0; j < count; ++j) {
    const Real length = N.row(j).norm();
    if (length > 0) {
      N.row(j) /= length;
    }
  }
}

}  // namespace incise::sim
