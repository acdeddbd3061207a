#include "remesh_fixtures.h"

#include <vector>

#include "sim/mesh/box_mesher.h"
#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/insertion.h"

namespace incise::sim::remesh::testing {

TetMesh unit_box() {
  return make_box_mesh(Vec3(1, 1, 1), Vec3i(4, 4, 4));
}

TetMesh two_label_box() {
  TetMesh mesh = unit_box();
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Real x = 0;
    for (int k = 0; k < 4; ++k)
      x += mesh.rest(mesh.tets(t, k), 0) / 4;
    mesh.labels(t) = x < 0.5 ? 0 : 1;
  }
  return mesh;
}

TetMesh jittered_two_label_box(unsigned seed) {
  TetMesh mesh = two_label_box();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> offset(-0.05, 0.05);  // cells are 0.25 wide
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Vec3 p = row3(mesh.rest, i);
    if (p.minCoeff() == 0 || p.maxCoeff() == 1 || p.x() == 0.5) continue;
    for (int c = 0; c < 3; ++c)
      mesh.rest(i, c) += offset(rng);
  }
  mesh.x = mesh.rest;
  return mesh;
}

namespace {

int random_tet(const RemeshMesh& mesh, std::mt19937& rng) {
  std::uniform_int_distribution<int> slot(0, mesh.num_tet_slots() - 1);
  for (;;) {
    const int t = slot(rng);
    if (mesh.tet_alive(t)) return t;
  }
}

// A random constrained face (tet, face index), found by sampling tets.
std::pair<int, int> random_constrained_face(const RemeshMesh& mesh, std::mt19937& rng) {
  for (;;) {
    const int t = random_tet(mesh, rng);
    const int k = static_cast<int>(rng() % 4);
    if (mesh.face_parent(t, k) >= 0) return {t, k};
  }
}

Real dyadic(std::mt19937& rng, int numerator_max) {
  return static_cast<Real>(1 + rng() % numerator_max) / 16;
}

}  // namespace

InsertResult random_insertion(RemeshMesh& mesh, int kind, std::mt19937& rng) {
  InsertResult result;
  if (kind == 0) {
    const int t = random_tet(mesh, rng);
    std::uniform_real_distribution<Real> weight(0.1, 1.0);
    Vec3 p = Vec3::Zero();
    Real total = 0;
    for (int k = 0; k < 4; ++k) {
      const Real w = weight(rng);
      p += w * mesh.point(mesh.tet(t)[k]);
      total += w;
    }
    result = insert_in_tet(mesh, t, p / total);
  } else if (kind == 1 || kind == 3) {
    int t = random_tet(mesh, rng);
    int k = static_cast<int>(rng() % 4);
    if (kind == 3) std::tie(t, k) = random_constrained_face(mesh, rng);
    const TetVertices& v = mesh.tet(t);
    const Real s = dyadic(rng, 7);  // s + u <= 14 / 16 < 1: strictly inside the face
    const Real u = dyadic(rng, 7);
    const Vec3 p =
        point_on_face(mesh, v[kTetFaces[k][0]], v[kTetFaces[k][1]], v[kTetFaces[k][2]], s, u);
    result = insert_on_face(mesh, t, k, p);
  } else {
    int t = random_tet(mesh, rng);
    int k = static_cast<int>(rng() % 4);
    if (kind == 4) std::tie(t, k) = random_constrained_face(mesh, rng);
    const int e = static_cast<int>(rng() % 3);
    const int a = mesh.tet(t)[kTetFaces[k][e]];
    const int b = mesh.tet(t)[kTetFaces[k][(e + 1) % 3]];
    result = insert_on_edge(mesh, a, b, point_on_edge(mesh, a, b, dyadic(rng, 15)));
  }
  return result;
}

}  // namespace incise::sim::remesh::testing
