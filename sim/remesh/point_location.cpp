#include "sim/remesh/point_location.h"

#include "sim/remesh/predicates.h"

namespace incise::sim::remesh {
namespace {

// orientation of t with p in place of local vertex k: > 0 if p is on the side of face k where t
// is, < 0 if p lies beyond the face, 0 on its plane.
int side_of_face(const RemeshMesh& mesh, int t, int k, const Vec3& p) {
  std::array<Vec3, 4> x;
  for (int j = 0; j < 4; ++j)
    x[j] = j == k ? p : mesh.point(mesh.tet(t)[j]);
  return orientation(x[0], x[1], x[2], x[3]);
}

}  // namespace

Location locate(const RemeshMesh& mesh, int start, const Vec3& p, int max_steps) {
  if (max_steps <= 0) max_steps = mesh.num_tets();
  Location where;
  int cur = start;
  for (int step = 0; step < max_steps; ++step) {
    int sides[4];
    int beyond = -1;
    for (int i = 0; i < 4 && beyond < 0; ++i) {
      const int k = (i + step) % 4;
      sides[k] = side_of_face(mesh, cur, k, p);
      if (sides[k] < 0) beyond = k;
    }
    if (beyond >= 0) {
      if (mesh.neighbor(cur, beyond) < 0 || mesh.face_parent(cur, beyond) >= 0) {
        where.kind = LocationKind::kBeyondConstraint;
        where.tet = cur;
        where.face = beyond;
        return where;
      }
      cur = mesh.neighbor(cur, beyond);
      continue;
    }
    // p is in the closure of cur: the faces whose plane holds it say where.
    where.tet = cur;
    int zeros = 0, on[4];
    for (int k = 0; k < 4; ++k) {
      if (sides[k] == 0) on[zeros++] = k;
    }
    if (zeros == 0) {
      where.kind = LocationKind::kInTet;
    } else if (zeros == 1) {
      where.kind = LocationKind::kOnFace;
      where.face = on[0];
    } else if (zeros == 2) {
      // On both faces on[0] and on[1]: the edge of the two other vertices.
      where.kind = LocationKind::kOnEdge;
      for (int k = 0; k < 4; ++k) {
        if (k == on[0] || k == on[1]) continue;
        (where.a < 0 ? where.a : where.b) = mesh.tet(cur)[k];
      }
    } else {
      where.kind = LocationKind::kOnVertex;
      for (int k = 0; k < 4; ++k) {
        if (sides[k] != 0) where.a = mesh.tet(cur)[k];
      }
    }
    return where;
  }
  return where;
}

InsertResult insert_at(RemeshMesh& mesh, const Location& where, const Vec3& p) {
  switch (where.kind) {
    case LocationKind::kInTet:
      return insert_in_tet(mesh, where.tet, p);
    case LocationKind::kOnFace:
      return insert_on_face(mesh, where.tet, where.face, p);
    case LocationKind::kOnEdge:
      return insert_on_edge(mesh, where.a, where.b, p);
    default:
      return {};
  }
}

}  // namespace incise::sim::remesh
