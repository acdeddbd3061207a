#include "sim/remesh/remesh_validity.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/predicates.h"

namespace incise::sim::remesh {
namespace {

FaceKey key_of(const RemeshMesh& mesh, int t, int k) {
  const TetVertices& v = mesh.tet(t);
  return face_key(v[kTetFaces[k][0]], v[kTetFaces[k][1]], v[kTetFaces[k][2]]);
}

std::string where(int t, int k) {
  return "tet " + std::to_string(t) + " face " + std::to_string(k);
}

// Within the parent of constrained face k of t: for each edge of the face, walks around the
// edge on t's side to the next constrained face; if that has the same parent the edge is inside
// the original face, and the sub-faces must be 2D Delaunay.
std::string check_subface_edges(const RemeshMesh& mesh, int t, int k) {
  const TetVertices& tv = mesh.tet(t);
  const int parent = mesh.face_parent(t, k);
  for (int e = 0; e < 3; ++e) {
    const int u = tv[kTetFaces[k][e]], w = tv[kTetFaces[k][(e + 1) % 3]];
    int cur = t, came_through = k;
    for (int steps = 0; steps < 1000; ++steps) {
      // The other face of cur holding u and w.
      int next_face = -1;
      for (int j = 0; j < 4; ++j) {
        const int x = mesh.tet(cur)[j];
        if (x != u && x != w && j != came_through) next_face = j;
      }
      if (mesh.face_parent(cur, next_face) >= 0) {
        // Another parent: an edge of the original face. The same face, reached around the
        // edge: a free edge of a lone (frozen) constrained face.
        if (mesh.face_parent(cur, next_face) != parent) break;
        if (key_of(mesh, cur, next_face) == key_of(mesh, t, k)) break;
        // That sub-face holds u, w and the vertex of cur that is neither u, w nor opposite it.
        int x = -1;
        for (int j = 0; j < 4; ++j) {
          const int y = mesh.tet(cur)[j];
          if (y != u && y != w && j != next_face) x = y;
        }
        if (in_circumsphere(mesh, t, x)) {
          return "sub-faces of facet " + std::to_string(parent) + " not 2D Delaunay at edge (" +
                 std::to_string(u) + ", " + std::to_string(w) + ")";
        }
        break;
      }
      const int other = mesh.neighbor(cur, next_face);
      if (other < 0) break;
      for (int j = 0; j < 4; ++j) {
        if (mesh.neighbor(other, j) == cur) came_through = j;
      }
      cur = other;
    }
  }
  return "";
}

}  // namespace

std::string check_remesh_mesh(const RemeshMesh& mesh) {
  std::map<FaceKey, int> face_uses;
  std::map<FaceKey, int> subface_parent;
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const TetVertices& v = mesh.tet(t);
    for (int k = 0; k < 4; ++k) {
      if (v[k] < 0 || v[k] >= mesh.num_vertex_slots() || !mesh.vertex_alive(v[k])) {
        return "tet " + std::to_string(t) + " uses a dead vertex";
      }
      for (int j = 0; j < k; ++j) {
        if (v[j] == v[k]) return "tet " + std::to_string(t) + " repeats a vertex";
      }
    }
    if (orientation(mesh.point(v[0]), mesh.point(v[1]), mesh.point(v[2]), mesh.point(v[3])) <= 0) {
      return "tet " + std::to_string(t) + " is not positively oriented";
    }
    for (int k = 0; k < 4; ++k) {
      const FaceKey key = key_of(mesh, t, k);
      if (++face_uses[key] > 2) return where(t, k) + " is shared by more than two tets";
      const int other = mesh.neighbor(t, k);
      const int parent = mesh.face_parent(t, k);
      if (other >= 0) {
        if (!mesh.tet_alive(other)) return where(t, k) + " has a dead neighbour";
        int back = -1;
        for (int j = 0; j < 4; ++j) {
          if (mesh.neighbor(other, j) == t) back = j;
        }
        if (back < 0 || key_of(mesh, other, back) != key) {
          return where(t, k) + ": adjacency not symmetric";
        }
        if (mesh.face_parent(other, back) != parent) {
          return where(t, k) + ": sides disagree on the parent";
        }
        if (mesh.label(other) != mesh.label(t) && parent < 0) {
          return where(t, k) + " separates labels but is not constrained";
        }
        if (!is_locally_delaunay(mesh, t, k)) return where(t, k) + " is not locally Delaunay";
      } else if (parent < 0) {
        return where(t, k) + " is on the boundary but not constrained";
      }
      if (parent >= 0) {
        if (parent >= mesh.num_facets()) {
          return where(t, k) + " has an unknown parent";
        }
        subface_parent[key] = parent;
        const std::string edges = check_subface_edges(mesh, t, k);
        if (!edges.empty()) return edges;
      }
    }
  }
  for (int x = 0; x < mesh.num_vertex_slots(); ++x) {
    if (!mesh.vertex_alive(x)) continue;
    const int t = mesh.vertex_tet(x);
    if (!mesh.tet_alive(t) || mesh.local_index(t, x) < 0) {
      return "vertex " + std::to_string(x) + " points to a tet not holding it";
    }
  }
  // Each facet: its sub-faces lie exactly in its plane and cover its area.
  const auto& originals = mesh.original_constrained_faces();
  const auto& facet_of = mesh.original_face_facets();
  std::vector<int> plane(mesh.num_facets(), -1);  // an original face of each facet
  std::vector<Real> expected(mesh.num_facets(), 0), area(mesh.num_facets(), 0);
  const auto triangle_area = [&](int a, int b, int c) {
    return 0.5 * (mesh.point(b) - mesh.point(a)).cross(mesh.point(c) - mesh.point(a)).norm();
  };
  for (size_t f = 0; f < originals.size(); ++f) {
    plane[facet_of[f]] = static_cast<int>(f);
    expected[facet_of[f]] += triangle_area(originals[f][0], originals[f][1], originals[f][2]);
  }
  for (const auto& [key, parent] : subface_parent) {
    const auto& o = originals[plane[parent]];
    for (int x : key) {
      if (orientation(mesh.point(o[0]), mesh.point(o[1]), mesh.point(o[2]), mesh.point(x)) != 0) {
        return "a sub-face of facet " + std::to_string(parent) + " is off its plane";
      }
    }
    area[parent] += triangle_area(key[0], key[1], key[2]);
  }
  for (int f = 0; f < mesh.num_facets(); ++f) {
    if (std::abs(area[f] - expected[f]) > 1e-12 * expected[f]) {
      return "the sub-faces of facet " + std::to_string(f) + " do not cover it";
    }
  }
  return "";
}

std::vector<std::array<int, 5>> canonical_tets(const RemeshMesh& mesh) {
  std::vector<std::array<int, 5>> rows;
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    TetVertices v = mesh.tet(t);
    std::sort(v.begin(), v.end());
    rows.push_back({v[0], v[1], v[2], v[3], mesh.label(t)});
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

Real remesh_volume(const RemeshMesh& mesh) {
  Real volume = 0;
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const TetVertices& v = mesh.tet(t);
    volume += signed_volume(mesh.point(v[0]), mesh.point(v[1]), mesh.point(v[2]), mesh.point(v[3]));
  }
  return volume;
}

}  // namespace incise::sim::remesh
