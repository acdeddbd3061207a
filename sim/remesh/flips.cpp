#include "sim/remesh/flips.h"

#include <algorithm>
#include <array>
#include <initializer_list>
#include <stdexcept>
#include <utility>

#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/predicates.h"

namespace incise::sim::remesh {
namespace {

int orient(const RemeshMesh& mesh, int a, int b, int c, int d) {
  return orientation(mesh.point(a), mesh.point(b), mesh.point(c), mesh.point(d));
}

// Puts the tet (a, b, c, d) in positive order; false if it is flat.
bool orient_positive(const RemeshMesh& mesh, TetVertices* v) {
  const int o = orient(mesh, (*v)[0], (*v)[1], (*v)[2], (*v)[3]);
  if (o < 0) std::swap((*v)[2], (*v)[3]);
  return o != 0;
}

int face_with_neighbor(const RemeshMesh& mesh, int t, int other) {
  for (int k = 0; k < 4; ++k) {
    if (mesh.neighbor(t, k) == other) return k;
  }
  return -1;
}

bool holds(const RemeshMesh& mesh, int t, std::initializer_list<int> vertices) {
  for (int v : vertices) {
    if (mesh.local_index(t, v) < 0) return false;
  }
  return true;
}

// The parent of the face of t with vertices (a, b, c), which t must hold.
int parent_of(const RemeshMesh& mesh, int t, int a, int b, int c) {
  for (int k = 0; k < 4; ++k) {
    const int o = mesh.tet(t)[k];
    if (o != a && o != b && o != c) return mesh.face_parent(t, k);
  }
  return -1;
}

}  // namespace

bool in_circumsphere(const RemeshMesh& mesh, int t, int e) {
  const TetVertices& v = mesh.tet(t);
  return side_of_sphere_perturbed(mesh.point(v[0]), mesh.point(v[1]), mesh.point(v[2]),
                                  mesh.point(v[3]), mesh.point(e), v[0], v[1], v[2], v[3], e) > 0;
}

bool is_locally_delaunay(const RemeshMesh& mesh, int t, int k) {
  const int other = mesh.neighbor(t, k);
  if (other < 0 || mesh.face_parent(t, k) >= 0) return true;
  const int j = face_with_neighbor(mesh, other, t);
  return !in_circumsphere(mesh, t, mesh.tet(other)[j]);
}

FlipKind flip_face(RemeshMesh& mesh, int t, int k, std::vector<int>* created) {
  if (is_locally_delaunay(mesh, t, k)) return FlipKind::kNone;
  const int tn = mesh.neighbor(t, k);
  const TetVertices& tv = mesh.tet(t);
  const int p = tv[k];
  const int d = mesh.tet(tn)[face_with_neighbor(mesh, tn, t)];
  const std::array<int, 3> face = {tv[kTetFaces[k][0]], tv[kTetFaces[k][1]], tv[kTetFaces[k][2]]};
  // Where the segment pd meets the plane of the face, edge by edge: +1 on the face's side of
  // the edge, 0 on the edge's line, -1 beyond it.
  int num_beyond = 0, num_on = 0, beyond = -1, on = -1;
  for (int e = 0; e < 3; ++e) {
    const int u = face[e], w = face[(e + 1) % 3], o = face[(e + 2) % 3];
    const int s = orient(mesh, u, w, p, d) * orient(mesh, u, w, p, o);
    if (s < 0) ++num_beyond, beyond = e;
    if (s == 0) ++num_on, on = e;
  }
  const int label = mesh.label(t);
  std::vector<NewTet> tets;
  std::vector<ConstrainedFace> constrained;
  std::vector<int> old = {t, tn};
  FlipKind kind = FlipKind::kNone;
  if (num_beyond == 0 && num_on == 0) {  // 2-3
    kind = FlipKind::k23;
    for (int e = 0; e < 3; ++e)
      tets.push_back({{p, d, face[e], face[(e + 1) % 3]}, label});
  } else if (num_beyond == 1 || (num_beyond == 0 && num_on == 1)) {
    const int e = num_beyond == 1 ? beyond : on;
    const int u = face[e], w = face[(e + 1) % 3], o = face[(e + 2) % 3];
    std::vector<int> ring;
    const bool open = mesh.edge_ring(u, w, t, &ring);
    if (num_beyond == 1) {  // 3-2: the edge uw must be inside a single region
      if (open || ring.size() != 3) return FlipKind::kNone;
      for (int r : ring) {
        for (int j = 0; j < 4; ++j) {
          const int x = mesh.tet(r)[j];
          if (x != u && x != w && mesh.face_parent(r, j) >= 0) return FlipKind::kNone;
        }
      }
      const int third = ring[0] != t && ring[0] != tn
                            ? ring[0]
                            : (ring[1] != t && ring[1] != tn ? ring[1] : ring[2]);
      if (!holds(mesh, third, {p, d})) return FlipKind::kNone;
      old.push_back(third);
      kind = FlipKind::k32;
      tets.push_back({{p, d, o, u}, label});
      tets.push_back({{p, d, o, w}, label});
    } else if (open) {  // 2-2 on the boundary
      if (ring.size() != 2) return FlipKind::kNone;
      const int parent = parent_of(mesh, t, u, w, p);
      if (parent < 0 || parent != parent_of(mesh, tn, u, w, d)) return FlipKind::kNone;
      tets.push_back({{p, d, o, u}, label});
      tets.push_back({{p, d, o, w}, label});
      constrained.push_back({face_key(p, d, u), parent});
      constrained.push_back({face_key(p, d, w), parent});
      kind = FlipKind::k22;
    } else {  // 4-4, inside a region or across one interface face pair
      if (ring.size() != 4) return FlipKind::kNone;
      int t3 = -1, t4 = -1;
      for (int r : ring) {
        if (r == t || r == tn) continue;
        if (holds(mesh, r, {d})) t3 = r;
        if (holds(mesh, r, {p})) t4 = r;
      }
      if (t3 < 0 || t4 < 0 || t3 == t4) return FlipKind::kNone;
      int x = -1;
      for (int v : mesh.tet(t3)) {
        if (v != u && v != w && v != d) x = v;
      }
      const int parent_p = parent_of(mesh, t, u, w, p);
      const int parent_d = parent_of(mesh, tn, u, w, d);
      if (parent_p != parent_d || parent_of(mesh, t3, u, w, x) >= 0) return FlipKind::kNone;
      const int other_label = mesh.label(t3);
      old.push_back(t3);
      old.push_back(t4);
      kind = FlipKind::k44;
      tets.push_back({{p, d, o, u}, label});
      tets.push_back({{p, d, o, w}, label});
      tets.push_back({{p, d, x, u}, other_label});
      tets.push_back({{p, d, x, w}, other_label});
      if (parent_p >= 0) {
        constrained.push_back({face_key(p, d, u), parent_p});
        constrained.push_back({face_key(p, d, w), parent_p});
      }
    }
  } else {
    return FlipKind::kNone;
  }
  for (NewTet& nt : tets) {
    if (!orient_positive(mesh, &nt.v)) return FlipKind::kNone;
  }
  mesh.replace_tets(old, tets, constrained, created);
  return kind;
}

int restore_delaunay(RemeshMesh& mesh, std::span<const int> seeds, FlipCounts* counts) {
  // Entries name a face by its tet and the vertex opposite it, so that a stale entry (the tet
  // was flipped away, its slot maybe reused) is recognised and skipped.
  std::vector<std::pair<int, int>> queue;
  for (int t : seeds) {
    for (int k = 0; k < 4; ++k)
      queue.emplace_back(t, mesh.tet(t)[k]);
  }
  int flips = 0;
  std::vector<int> created;
  while (!queue.empty()) {
    const auto [t, opposite] = queue.back();
    queue.pop_back();
    if (!mesh.tet_alive(t)) continue;
    const int k = mesh.local_index(t, opposite);
    if (k < 0) continue;
    const FlipKind kind = flip_face(mesh, t, k, &created);
    if (kind == FlipKind::kNone) continue;
    ++flips;
    if (counts != nullptr) ++counts->of[static_cast<int>(kind)];
    for (int c : created) {
      for (int j = 0; j < 4; ++j)
        queue.emplace_back(c, mesh.tet(c)[j]);
    }
  }
  return flips;
}

int make_constrained_delaunay(RemeshMesh& mesh) {
  std::vector<int> all;
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (mesh.tet_alive(t)) all.push_back(t);
  }
  restore_delaunay(mesh, all, nullptr);
  int frozen = 0;
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    for (int k = 0; k < 4; ++k) {
      if (is_locally_delaunay(mesh, t, k)) continue;
      mesh.constrain_face(t, k);
      ++frozen;
    }
  }
  return frozen;
}

}  // namespace incise::sim::remesh
