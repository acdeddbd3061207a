#include "sim/remesh/insertion.h"

#include <vector>

#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/predicates.h"

namespace incise::sim::remesh {
namespace {

InsertResult refused(InsertStatus status) {
  InsertResult result;
  result.status = status;
  return result;
}

bool all_positive(const RemeshMesh& mesh, const std::vector<NewTet>& tets, int v, const Vec3& p) {
  for (const NewTet& nt : tets) {
    std::array<Vec3, 4> x;
    for (int k = 0; k < 4; ++k)
      x[k] = nt.v[k] == v ? p : mesh.point(nt.v[k]);
    if (orientation(x[0], x[1], x[2], x[3]) <= 0) return false;
  }
  return true;
}

// Adds the vertex, replaces the tets and restores the Delaunay property.
InsertResult commit(RemeshMesh& mesh, const std::vector<int>& old, std::vector<NewTet>& tets,
                    const std::vector<ConstrainedFace>& constrained, int placeholder,
                    const Vec3& p) {
  InsertResult result;
  mesh.begin_changes();
  result.vertex = mesh.add_vertex(p);
  for (NewTet& nt : tets) {
    for (int& v : nt.v)
      v = v == placeholder ? result.vertex : v;
  }
  std::vector<ConstrainedFace> faces = constrained;
  for (ConstrainedFace& f : faces) {
    for (int& v : f.key)
      v = v == placeholder ? result.vertex : v;
    f.key = face_key(f.key[0], f.key[1], f.key[2]);
  }
  std::vector<int> created;
  mesh.replace_tets(old, tets, faces, &created);
  restore_delaunay(mesh, created, &result.flips);
  result.changes = mesh.end_changes();
  result.delaunay_restored = true;
  for (int t : result.changes.created) {
    for (int k = 0; k < 4; ++k) {
      if (!is_locally_delaunay(mesh, t, k)) result.delaunay_restored = false;
    }
  }
  result.status = InsertStatus::kInserted;
  return result;
}

// New vertices are named by this placeholder until the geometry has been checked.
constexpr int kNew = -7;

}  // namespace

Vec3 point_on_face(const RemeshMesh& mesh, int a, int b, int c, Real s, Real t) {
  const Vec3& pa = mesh.point(a);
  return pa + s * (mesh.point(b) - pa) + t * (mesh.point(c) - pa);
}

Vec3 point_on_edge(const RemeshMesh& mesh, int a, int b, Real s) {
  const Vec3& pa = mesh.point(a);
  return pa + s * (mesh.point(b) - pa);
}

InsertResult insert_in_tet(RemeshMesh& mesh, int t, const Vec3& p) {
  std::vector<NewTet> tets;
  for (int k = 0; k < 4; ++k) {
    TetVertices v = mesh.tet(t);
    v[k] = kNew;
    tets.push_back({v, mesh.label(t)});
  }
  if (!all_positive(mesh, tets, kNew, p)) return {};
  return commit(mesh, {t}, tets, {}, kNew, p);
}

InsertResult insert_on_face(RemeshMesh& mesh, int t, int k, const Vec3& p) {
  const TetVertices& tv = mesh.tet(t);
  const int a = tv[kTetFaces[k][0]], b = tv[kTetFaces[k][1]], c = tv[kTetFaces[k][2]];
  const int parent = mesh.face_parent(t, k);
  if (parent >= 0 && orientation(mesh.point(a), mesh.point(b), mesh.point(c), p) != 0) {
    return refused(InsertStatus::kOffConstraint);
  }
  std::vector<int> old = {t};
  if (mesh.neighbor(t, k) >= 0) old.push_back(mesh.neighbor(t, k));
  std::vector<NewTet> tets;
  for (int o : old) {
    for (int j = 0; j < 4; ++j) {
      const int v = mesh.tet(o)[j];
      if (v != a && v != b && v != c) continue;  // split by replacing each face corner by p
      TetVertices split = mesh.tet(o);
      split[j] = kNew;
      tets.push_back({split, mesh.label(o)});
    }
  }
  std::vector<ConstrainedFace> constrained;
  if (parent >= 0) {
    constrained = {{{a, b, kNew}, parent}, {{b, c, kNew}, parent}, {{c, a, kNew}, parent}};
  }
  if (!all_positive(mesh, tets, kNew, p)) return {};
  return commit(mesh, old, tets, constrained, kNew, p);
}

InsertResult insert_on_edge(RemeshMesh& mesh, int a, int b, const Vec3& p) {
  const int start = mesh.find_edge_tet(a, b);
  if (start < 0) return {};
  std::vector<int> ring;
  const bool open = mesh.edge_ring(a, b, start, &ring);
  std::vector<NewTet> tets;
  std::vector<ConstrainedFace> constrained;
  for (int r : ring) {
    const int la = mesh.local_index(r, a), lb = mesh.local_index(r, b);
    TetVertices half = mesh.tet(r);
    half[la] = kNew;
    tets.push_back({half, mesh.label(r)});
    half = mesh.tet(r);
    half[lb] = kNew;
    tets.push_back({half, mesh.label(r)});
    for (int j = 0; j < 4; ++j) {
      if (j == la || j == lb || mesh.face_parent(r, j) < 0) continue;
      int x = -1;  // the third vertex of the face opposite j
      for (int i = 0; i < 4; ++i) {
        if (i != la && i != lb && i != j) x = mesh.tet(r)[i];
      }
      constrained.push_back({{a, x, kNew}, mesh.face_parent(r, j)});
      constrained.push_back({{b, x, kNew}, mesh.face_parent(r, j)});
    }
  }
  if (!open && constrained.size() == 2 * 2) {  // one face: two sub-faces from each of its two tets
    return refused(InsertStatus::kOnFreeConstraintEdge);
  }
  if ((open || !constrained.empty()) && !collinear(mesh.point(a), mesh.point(b), p)) {
    return refused(InsertStatus::kOffConstraint);
  }
  if (!all_positive(mesh, tets, kNew, p)) return {};
  return commit(mesh, ring, tets, constrained, kNew, p);
}

}  // namespace incise::sim::remesh
