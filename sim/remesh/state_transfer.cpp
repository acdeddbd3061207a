#include "sim/remesh/state_transfer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/LU>

#include "sim/mesh/mesh_quality.h"

namespace incise::sim::remesh {

Weights4 barycentric(const std::array<Vec3, 4>& corners, const Vec3& p) {
  Mat3 edges;
  edges << corners[1] - corners[0], corners[2] - corners[0], corners[3] - corners[0];
  Real longest = 0;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < i; ++j)
      longest = std::max(longest, (corners[i] - corners[j]).norm());
  }
  if (is_degenerate(edges.determinant() / 6, longest)) {
    throw std::invalid_argument("barycentric coordinates in a flat tet");
  }
  const Vec3 tail = edges.partialPivLu().solve(p - corners[0]);
  Weights4 w;
  w << 1 - tail.sum(), tail;
  return w;
}

Vec3 interpolate(const std::array<Vec3, 4>& values, const Weights4& w) {
  return w[0] * values[0] + w[1] * values[1] + w[2] * values[2] + w[3] * values[3];
}

Real interpolate(const std::array<Real, 4>& values, const Weights4& w) {
  return w[0] * values[0] + w[1] * values[1] + w[2] * values[2] + w[3] * values[3];
}

Vec3 interpolate_rows(const Points& values, const std::array<int, 4>& rows, const Weights4& w) {
  return interpolate(
      {row3(values, rows[0]), row3(values, rows[1]), row3(values, rows[2]), row3(values, rows[3])},
      w);
}

Vec3 displacement_at(const Points& rest, const Points& x, const Tets& tets,
                     const std::vector<char>* alive, const Vec3& p) {
  Real best = -std::numeric_limits<Real>::infinity();
  Vec3 u = Vec3::Zero();
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    if (alive != nullptr && (*alive)[static_cast<std::size_t>(t)] == 0) continue;
    const std::array<int, 4> n{tets(t, 0), tets(t, 1), tets(t, 2), tets(t, 3)};
    const Weights4 w =
        barycentric({row3(rest, n[0]), row3(rest, n[1]), row3(rest, n[2]), row3(rest, n[3])}, p);
    if (w.minCoeff() <= best) continue;
    best = w.minCoeff();
    u = interpolate_rows(x, n, w) - interpolate_rows(rest, n, w);
    if (best >= 0) break;
  }
  return u;
}

LocatedInsertion insert_located(RemeshMesh& mesh, const Location& where, const Vec3& p) {
  LocatedInsertion out;
  if (where.tet < 0 || !mesh.tet_alive(where.tet)) return out;
  out.inserted.host = mesh.tet(where.tet);
  std::array<Vec3, 4> corners;
  for (int k = 0; k < 4; ++k)
    corners[k] = mesh.point(out.inserted.host[k]);
  out.inserted.weights = barycentric(corners, p);
  out.inserted.rest_point = p;
  out.result = insert_at(mesh, where, p);
  out.inserted.vertex = out.result.vertex;
  return out;
}

}  // namespace incise::sim::remesh
