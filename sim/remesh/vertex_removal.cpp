#include "sim/remesh/vertex_removal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/predicates.h"
#include "sim/remesh/tet_shape.h"

namespace incise::sim::remesh {
namespace {

struct OpenFace {
  std::array<int, 3> v;  // oriented so that the tet still to build lies on its positive side
  FaceKey key;
  bool closed = false;
};

Real triangle_area(const RemeshMesh& mesh, const FaceKey& f) {
  const Vec3& a = mesh.point(f[0]);
  return 0.5 * (mesh.point(f[1]) - a).cross(mesh.point(f[2]) - a).norm();
}

Real tet_volume(const RemeshMesh& mesh, const TetVertices& t) {
  return signed_volume(mesh.point(t[0]), mesh.point(t[1]), mesh.point(t[2]), mesh.point(t[3]));
}

bool close_enough(Real a, Real b) {
  return std::abs(a - b) <= 1e-10 * std::max(std::abs(a), std::abs(b));
}

// One side of the star: its tets, link vertices, and the constrained faces through v that
// bound it (parent -> their vertices other than v, and their total area).
struct Side {
  std::vector<int> tets;
  std::vector<int> link;
  std::map<int, std::vector<int>> facet_vertices;
  std::map<int, Real> facet_area;
  Real volume = 0;
  int label = 0;
};

// Gift-wraps one side; appends the new tets and the new constrained faces. False if stuck.
bool fill_side(const RemeshMesh& mesh, int v, const Side& side, std::vector<NewTet>* tets,
               std::vector<ConstrainedFace>* faces) {
  std::vector<OpenFace> open;
  for (int t : side.tets) {
    const int lv = mesh.local_index(t, v);
    const TetVertices& tv = mesh.tet(t);
    const std::array<int, 3> f = {tv[kTetFaces[lv][0]], tv[kTetFaces[lv][2]], tv[kTetFaces[lv][1]]};
    open.push_back({f, face_key(f[0], f[1], f[2])});
  }
  const auto p = [&](int i) -> const Vec3& { return mesh.point(i); };
  std::map<int, Real> new_area;
  Real volume = 0;
  const size_t max_tets = 8 * side.link.size() * side.link.size();
  size_t num_tets = 0;
  for (size_t i = 0; i < open.size(); ++i) {
    if (open[i].closed) continue;
    open[i].closed = true;
    const auto [a, b, c] = open[i].v;
    int best = -1;
    for (int q : side.link) {
      if (q == a || q == b || q == c || orientation(p(a), p(b), p(c), p(q)) <= 0) continue;
      if (best < 0 ||
          side_of_sphere_perturbed(p(a), p(b), p(c), p(best), p(q), a, b, c, best, q) > 0) {
        best = q;
      }
    }
    if (best < 0) {  // nothing beyond: the face must close on a constrained face through v
      int parent = -1;
      for (const auto& [candidate, vertices] : side.facet_vertices) {
        const auto on = [&](int x) {
          return std::find(vertices.begin(), vertices.end(), x) != vertices.end();
        };
        if (on(a) && on(b) && on(c)) parent = candidate;
      }
      if (parent < 0) return false;
      faces->push_back({open[i].key, parent});
      new_area[parent] += triangle_area(mesh, open[i].key);
      continue;
    }
    if (++num_tets > max_tets) return false;
    const TetVertices t = {a, b, c, best};
    tets->push_back({t, side.label});
    volume += tet_volume(mesh, t);
    for (int k = 0; k < 3; ++k) {  // the faces opposite a, b, c, oriented out of the new tet
      const std::array<int, 3> g = {t[kTetFaces[k][0]], t[kTetFaces[k][1]], t[kTetFaces[k][2]]};
      const FaceKey key = face_key(g[0], g[1], g[2]);
      const auto same = std::find_if(open.begin(), open.end(),
                                     [&](const OpenFace& o) { return same_key(o.key, key); });
      if (same == open.end()) {
        open.push_back({g, key});
      } else if (!same->closed) {
        same->closed = true;
      } else {
        return false;  // a third tet on one face: the wrapping overlaps itself
      }
    }
  }
  if (!close_enough(volume, side.volume)) return false;
  for (const auto& [parent, area] : side.facet_area) {
    if (!close_enough(area, new_area[parent])) return false;
  }
  return true;
}

}  // namespace

RemoveResult remove_vertex(RemeshMesh& mesh, int v, Real min_altitude) {
  if (mesh.is_original(v)) return {RemoveStatus::kOriginalVertex, {}};
  std::vector<int> star;
  mesh.star(v, &star);
  // Sides: connected through the unconstrained faces around v.
  std::vector<int> side_of(star.size(), -1);
  std::vector<Side> sides;
  for (size_t s = 0; s < star.size(); ++s) {
    if (side_of[s] >= 0) continue;
    Side side;
    side.label = mesh.label(star[s]);
    side.tets.push_back(star[s]);
    side_of[s] = static_cast<int>(sides.size());
    for (size_t i = 0; i < side.tets.size(); ++i) {
      const int t = side.tets[i];
      for (int k = 0; k < 4; ++k) {
        const int other = mesh.neighbor(t, k);
        if (mesh.tet(t)[k] == v || other < 0 || mesh.face_parent(t, k) >= 0) continue;
        const size_t j = std::find(star.begin(), star.end(), other) - star.begin();
        if (side_of[j] >= 0) continue;
        side_of[j] = side_of[s];
        side.tets.push_back(other);
      }
    }
    for (int t : side.tets) {
      side.volume += tet_volume(mesh, mesh.tet(t));
      for (int k = 0; k < 4; ++k) {
        const int x = mesh.tet(t)[k];
        if (x != v && std::find(side.link.begin(), side.link.end(), x) == side.link.end()) {
          side.link.push_back(x);
        }
        const int parent = mesh.face_parent(t, k);
        if (x == v || parent < 0) continue;
        std::vector<int>& on = side.facet_vertices[parent];
        FaceKey key = {-1, -1, -1};
        int n = 0;
        for (int j = 0; j < 4; ++j) {
          const int y = mesh.tet(t)[j];
          if (j == k) continue;
          key[n++] = y;
          if (y != v && std::find(on.begin(), on.end(), y) == on.end()) on.push_back(y);
        }
        side.facet_area[parent] += triangle_area(mesh, face_key(key[0], key[1], key[2]));
      }
    }
    sides.push_back(std::move(side));
  }
  std::vector<NewTet> tets;
  std::vector<ConstrainedFace> faces;
  for (const Side& side : sides) {
    if (!fill_side(mesh, v, side, &tets, &faces)) return {RemoveStatus::kCannotRemoveNow, {}};
  }
  if (min_altitude > 0) {
    for (const NewTet& t : tets) {
      const TetShape shape =
          tet_shape(mesh.point(t.v[0]), mesh.point(t.v[1]), mesh.point(t.v[2]), mesh.point(t.v[3]));
      if (shape.min_altitude < min_altitude) return {RemoveStatus::kCannotRemoveNow, {}};
    }
  }
  // Both sides of a label interface must agree on its new sub-faces.
  std::map<FaceKey, int> face_count;
  for (const ConstrainedFace& f : faces)
    ++face_count[f.key];
  std::map<int, int> parent_sides;  // how many sides each parent bounds
  for (const Side& side : sides) {
    for (const auto& entry : side.facet_area)
      ++parent_sides[entry.first];
  }
  for (const ConstrainedFace& f : faces) {
    if (face_count[f.key] != parent_sides[f.parent]) return {RemoveStatus::kCannotRemoveNow, {}};
  }
  // Kept for a roll-back: the old tets and the constrained faces through v.
  std::vector<NewTet> old_tets;
  std::vector<ConstrainedFace> old_faces;
  for (int t : star) {
    old_tets.push_back({mesh.tet(t), mesh.label(t)});
    for (int k = 0; k < 4; ++k) {
      if (mesh.tet(t)[k] == v || mesh.face_parent(t, k) < 0) continue;
      const TetVertices& tv = mesh.tet(t);
      old_faces.push_back({face_key(tv[kTetFaces[k][0]], tv[kTetFaces[k][1]], tv[kTetFaces[k][2]]),
                           mesh.face_parent(t, k)});
    }
  }
  mesh.begin_changes();
  std::vector<int> created;
  mesh.replace_tets(star, tets, faces, &created);
  bool delaunay = true;
  for (int t : created) {
    for (int k = 0; k < 4 && delaunay; ++k)
      delaunay = is_locally_delaunay(mesh, t, k);
  }
  if (!delaunay) {
    std::vector<int> new_ids = created;
    mesh.replace_tets(new_ids, old_tets, old_faces, &created);
    return {RemoveStatus::kCannotRemoveNow, mesh.end_changes()};
  }
  mesh.free_vertex(v);
  return {RemoveStatus::kRemoved, mesh.end_changes()};
}

}  // namespace incise::sim::remesh
