#include "sim/remesh/remesh_mesh.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/predicates.h"

namespace incise::sim::remesh {

FaceKey face_key(int a, int b, int c) {
  if (a > b) std::swap(a, b);
  if (b > c) std::swap(b, c);
  if (a > b) std::swap(a, b);
  return {a, b, c};
}

namespace {

FaceKey tet_face_key(const TetVertices& t, int k) {
  return face_key(t[kTetFaces[k][0]], t[kTetFaces[k][1]], t[kTetFaces[k][2]]);
}

}  // namespace

RemeshMesh::RemeshMesh(const TetMesh& mesh) {
  const int n = mesh.num_nodes();
  const int m = mesh.num_tets();
  points_.resize(n);
  for (int i = 0; i < n; ++i)
    points_[i] = row3(mesh.rest, i);
  vertex_tet_.assign(n, -1);
  num_original_vertices_ = n;
  const Tets adjacency = face_neighbours(mesh.tets);
  tets_.resize(m);
  neighbors_.resize(m);
  parents_.resize(m);
  labels_.resize(m);
  for (int t = 0; t < m; ++t) {
    for (int k = 0; k < 4; ++k) {
      tets_[t][k] = mesh.tets(t, k);
      neighbors_[t][k] = adjacency(t, k);
      parents_[t][k] = -1;
    }
    labels_[t] = mesh.labels.size() == m ? mesh.labels(t) : 0;
    const TetVertices& v = tets_[t];
    if (orientation(points_[v[0]], points_[v[1]], points_[v[2]], points_[v[3]]) <= 0) {
      throw std::invalid_argument("RemeshMesh: tet " + std::to_string(t) +
                                  " is not positively oriented");
    }
    for (int k = 0; k < 4; ++k)
      vertex_tet_[v[k]] = t;
  }
  // The constrained faces, each taken once (from the tet with the smaller id for an interface).
  std::vector<Taken> taken;
  for (int t = 0; t < m; ++t) {
    for (int k = 0; k < 4; ++k) {
      const int other = neighbors_[t][k];
      if (other >= 0 && (labels_[other] == labels_[t] || other < t)) continue;
      const TetVertices& v = tets_[t];
      original_faces_.push_back({v[kTetFaces[k][0]], v[kTetFaces[k][1]], v[kTetFaces[k][2]]});
      taken.push_back({t, k});
    }
  }
  group_facets(taken);
  num_vertices_ = static_cast<int>(
      std::count_if(vertex_tet_.begin(), vertex_tet_.end(), [](int t) { return t >= 0; }));
  num_tets_ = m;
}

void RemeshMesh::group_facets(const std::vector<Taken>& taken) {
  const int n = static_cast<int>(taken.size());
  std::vector<int> root(n);
  for (int i = 0; i < n; ++i)
    root[i] = i;
  const auto find = [&](int i) {
    while (root[i] != i)
      i = root[i] = root[root[i]];
    return i;
  };
  // The labels behind face i (inside its tet) and in front of it (-1 outside the mesh), as seen
  // from the plane of face `in_plane_of` (whose orientation may be the opposite).
  const auto labels_seen = [&](int i, int in_plane_of) {
    const auto& [t, k] = taken[i];
    const auto& f = original_faces_[in_plane_of];
    const int apex = tets_[t][k];
    const int behind = labels_[t];
    const int front = neighbors_[t][k] >= 0 ? labels_[neighbors_[t][k]] : -1;
    const bool same_side =
        orientation(points_[f[0]], points_[f[1]], points_[f[2]], points_[apex]) < 0;
    return same_side ? std::pair(behind, front) : std::pair(front, behind);
  };
  std::map<std::pair<int, int>, std::vector<int>> faces_of_edge;
  for (int i = 0; i < n; ++i) {
    const auto& f = original_faces_[i];
    for (int e = 0; e < 3; ++e) {
      faces_of_edge[std::minmax(f[e], f[(e + 1) % 3])].push_back(i);
    }
  }
  for (const auto& [edge, faces] : faces_of_edge) {
    for (size_t a = 0; a < faces.size(); ++a) {
      for (size_t b = a + 1; b < faces.size(); ++b) {
        const auto& f = original_faces_[faces[a]];
        const auto& g = original_faces_[faces[b]];
        bool coplanar = true;
        for (int x : g) {
          coplanar =
              coplanar && orientation(points_[f[0]], points_[f[1]], points_[f[2]], points_[x]) == 0;
        }
        if (coplanar && labels_seen(faces[a], faces[a]) == labels_seen(faces[b], faces[a])) {
          root[find(faces[a])] = find(faces[b]);
        }
      }
    }
  }
  std::vector<int> facet_of_root(n, -1);
  original_facet_.resize(n);
  for (int i = 0; i < n; ++i) {
    int& facet = facet_of_root[find(i)];
    if (facet < 0) facet = num_facets_++;
    original_facet_[i] = facet;
    const auto& [t, k] = taken[i];
    parents_[t][k] = facet;
    const int other = neighbors_[t][k];
    if (other < 0) continue;
    for (int j = 0; j < 4; ++j) {
      if (neighbors_[other][j] == t) parents_[other][j] = facet;
    }
  }
}

int RemeshMesh::local_index(int t, int v) const {
  for (int k = 0; k < 4; ++k) {
    if (tets_[t][k] == v) return k;
  }
  return -1;
}

void RemeshMesh::star(int v, std::vector<int>* tets) const {
  tets->clear();
  const int start = vertex_tet_[v];
  if (start < 0) return;
  tets->push_back(start);
  // Breadth-first across the faces holding v; the stars are small, so a linear membership
  // test beats a hash set.
  for (size_t i = 0; i < tets->size(); ++i) {
    const int t = (*tets)[i];
    const int lv = local_index(t, v);
    for (int k = 0; k < 4; ++k) {
      const int other = neighbors_[t][k];
      if (k == lv || other < 0) continue;
      if (std::find(tets->begin(), tets->end(), other) == tets->end()) tets->push_back(other);
    }
  }
}

bool RemeshMesh::edge_ring(int a, int b, int start, std::vector<int>* tets) const {
  tets->clear();
  tets->push_back(start);
  bool open = false;
  for (size_t i = 0; i < tets->size(); ++i) {
    const int t = (*tets)[i];
    const int la = local_index(t, a);
    const int lb = local_index(t, b);
    for (int k = 0; k < 4; ++k) {
      if (k == la || k == lb) continue;  // the two faces holding the edge are the others
      const int other = neighbors_[t][k];
      if (other < 0) {
        open = true;
      } else if (std::find(tets->begin(), tets->end(), other) == tets->end()) {
        tets->push_back(other);
      }
    }
  }
  return open;
}

int RemeshMesh::find_edge_tet(int a, int b) const {
  std::vector<int> around;
  star(a, &around);
  for (int t : around) {
    if (local_index(t, b) >= 0) return t;
  }
  return -1;
}

int RemeshMesh::allocate_tet() {
  int t;
  if (!free_tets_.empty()) {
    t = free_tets_.back();
    free_tets_.pop_back();
  } else {
    t = num_tet_slots();
    tets_.push_back({});
    neighbors_.push_back({-1, -1, -1, -1});
    parents_.push_back({-1, -1, -1, -1});
    labels_.push_back(0);
  }
  ++num_tets_;
  if (journaling_) journal_created_.push_back(t);
  return t;
}

void RemeshMesh::free_tet(int t) {
  tets_[t] = {-1, -1, -1, -1};
  free_tets_.push_back(t);
  --num_tets_;
  if (!journaling_) return;
  const auto it = std::find(journal_created_.begin(), journal_created_.end(), t);
  if (it != journal_created_.end()) {
    journal_created_.erase(it);  // created and removed within the same operation
  } else {
    journal_removed_.push_back(t);
  }
}

void RemeshMesh::replace_tets(std::span<const int> old, std::span<const NewTet> created,
                              std::span<const ConstrainedFace> constrained,
                              std::vector<int>* created_ids) {
  if (in_old_.size() < tets_.size()) in_old_.resize(tets_.size(), 0);
  for (int t : old)
    in_old_[t] = 1;
  outer_.clear();
  for (int t : old) {
    for (int k = 0; k < 4; ++k) {
      const int other = neighbors_[t][k];
      if (other >= 0 && in_old_[other] != 0) continue;
      int other_face = -1;
      if (other >= 0) {
        for (int j = 0; j < 4; ++j) {
          if (neighbors_[other][j] == t) other_face = j;
        }
      }
      outer_.push_back({tet_face_key(tets_[t], k), other, other_face, parents_[t][k], false});
    }
  }
  for (int t : old)
    in_old_[t] = 0;
  for (int t : old)
    free_tet(t);
  new_ids_.clear();
  for (const NewTet& nt : created) {
    const int t = allocate_tet();
    tets_[t] = nt.v;
    labels_[t] = nt.label;
    neighbors_[t] = {-2, -2, -2, -2};  // -2: not linked yet
    parents_[t] = {-1, -1, -1, -1};
    new_ids_.push_back(t);
  }
  const auto constrained_parent = [&](const FaceKey& key) {
    for (const ConstrainedFace& c : constrained) {
      if (same_key(c.key, key)) return c.parent;
    }
    return -1;
  };
  face_slots_.clear();
  for (size_t i = 0; i < outer_.size(); ++i)
    face_slots_.push_back({outer_[i].key, static_cast<int>(i)});
  for (size_t i = 0; i < new_ids_.size(); ++i) {
    for (int k = 0; k < 4; ++k) {
      face_slots_.push_back(
          {tet_face_key(tets_[new_ids_[i]], k), -(4 * static_cast<int>(i) + k) - 1});
    }
  }
  // Outer faces sort before new faces of the same key (index >= 0 before < 0 when descending).
  std::sort(face_slots_.begin(), face_slots_.end(), [](const FaceSlot& a, const FaceSlot& b) {
    return !same_key(a.key, b.key) ? key_less(a.key, b.key) : a.index > b.index;
  });
  const auto new_tet = [&](int index) { return new_ids_[static_cast<size_t>(-index - 1) / 4]; };
  const auto new_face = [](int index) { return (-index - 1) % 4; };
  for (size_t begin = 0; begin < face_slots_.size();) {
    size_t end = begin + 1;
    while (end < face_slots_.size() && same_key(face_slots_[end].key, face_slots_[begin].key))
      ++end;
    const FaceSlot& first = face_slots_[begin];
    if (end - begin > 2) throw std::logic_error("replace_tets: a face is shared by three tets");
    if (end - begin == 2) {
      const FaceSlot& second = face_slots_[begin + 1];
      if (second.index >= 0) throw std::logic_error("replace_tets: an outside face appears twice");
      const int t = new_tet(second.index);
      const int k = new_face(second.index);
      if (first.index >= 0) {
        // A new tet glued to the cavity's boundary: it inherits the face's constraint.
        OuterFace& f = outer_[static_cast<size_t>(first.index)];
        f.glued = true;
        neighbors_[t][k] = f.tet;
        parents_[t][k] = f.parent;
        if (f.tet >= 0) neighbors_[f.tet][f.face] = t;
      } else {
        const int u = new_tet(first.index);
        const int l = new_face(first.index);
        neighbors_[t][k] = u;
        neighbors_[u][l] = t;
        parents_[t][k] = parents_[u][l] = constrained_parent(first.key);
      }
    } else if (first.index < 0) {
      // A new face on nothing: the new boundary, which must be a constrained face.
      const int parent = constrained_parent(first.key);
      if (parent < 0) throw std::logic_error("replace_tets: a new face is left open");
      neighbors_[new_tet(first.index)][new_face(first.index)] = -1;
      parents_[new_tet(first.index)][new_face(first.index)] = parent;
    }
    begin = end;
  }
  for (const OuterFace& f : outer_) {
    // A boundary face may go (a 2-2 flip or a removal re-triangulates the boundary); a face
    // with a tet behind it must be covered.
    if (!f.glued && f.tet >= 0)
      throw std::logic_error("replace_tets: an outside face is left uncovered");
  }
  for (int t : new_ids_) {
    for (int v : tets_[t])
      vertex_tet_[v] = t;
  }
  if (created_ids != nullptr) *created_ids = new_ids_;
}

int RemeshMesh::constrain_face(int t, int k) {
  const int other = neighbors_[t][k];
  if (other < 0 || parents_[t][k] >= 0) {
    throw std::invalid_argument("constrain_face: not an unconstrained interior face");
  }
  const int parent = num_facets_++;
  const TetVertices& v = tets_[t];
  original_faces_.push_back({v[kTetFaces[k][0]], v[kTetFaces[k][1]], v[kTetFaces[k][2]]});
  original_facet_.push_back(parent);
  parents_[t][k] = parent;
  for (int j = 0; j < 4; ++j) {
    if (neighbors_[other][j] == t) parents_[other][j] = parent;
  }
  return parent;
}

int RemeshMesh::add_vertex(const Vec3& p) {
  int v;
  if (!free_vertices_.empty()) {
    v = free_vertices_.back();
    free_vertices_.pop_back();
    points_[v] = p;
  } else {
    v = num_vertex_slots();
    points_.push_back(p);
    vertex_tet_.push_back(-1);
  }
  ++num_vertices_;
  return v;
}

void RemeshMesh::free_vertex(int v) {
  vertex_tet_[v] = -1;
  free_vertices_.push_back(v);
  --num_vertices_;
}

void RemeshMesh::begin_changes() {
  journaling_ = true;
  journal_removed_.clear();
  journal_created_.clear();
}

TetChanges RemeshMesh::end_changes() {
  journaling_ = false;
  return {journal_removed_, journal_created_};
}

TetMesh RemeshMesh::to_tet_mesh(std::vector<int>* vertex_ids) const {
  std::vector<int> compact(points_.size(), -1);
  std::vector<int> ids;
  for (int v = 0; v < num_vertex_slots(); ++v) {
    if (!vertex_alive(v)) continue;
    compact[v] = static_cast<int>(ids.size());
    ids.push_back(v);
  }
  Points rest(static_cast<Eigen::Index>(ids.size()), 3);
  for (size_t i = 0; i < ids.size(); ++i)
    rest.row(static_cast<Eigen::Index>(i)) = points_[ids[i]];
  Tets tets(num_tets_, 4);
  Eigen::VectorXi labels(num_tets_);
  int row = 0;
  for (int t = 0; t < num_tet_slots(); ++t) {
    if (!tet_alive(t)) continue;
    for (int k = 0; k < 4; ++k)
      tets(row, k) = compact[tets_[t][k]];
    labels(row++) = labels_[t];
  }
  if (vertex_ids != nullptr) *vertex_ids = ids;
  return make_tet_mesh(std::move(rest), std::move(tets), std::move(labels));
}

}  // namespace incise::sim::remesh
