#include "sim/cut/material_map.h"

#include <algorithm>
#include <utility>

#include <Eigen/LU>

namespace incise::sim::cut {

namespace {

Mat3 edges_of(const Points& points, const Tets& tets, int t) {
  const Vec3 o = row3(points, tets(t, 0));
  Mat3 d;
  for (int k = 1; k < 4; ++k)
    d.col(k - 1) = row3(points, tets(t, k)) - o;
  return d;
}

}  // namespace

std::optional<MaterialMap> material_map_at(const TetMesh& mesh, const Vec3& p, Real reach,
                                           Real min_volume_ratio) {
  int inside = -1, nearest = -1;
  Real nearest_distance2 = reach * reach;
  for (int t = 0; t < mesh.num_tets() && inside < 0; ++t) {
    Vec3 lo = row3(mesh.x, mesh.tets(t, 0)), hi = lo, centroid = lo;
    for (int k = 1; k < 4; ++k) {
      const Vec3 q = row3(mesh.x, mesh.tets(t, k));
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
      centroid += q;
    }
    const Real d2 = (0.25 * centroid - p).squaredNorm();
    if (d2 < nearest_distance2) {
      nearest_distance2 = d2;
      nearest = t;
    }
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    const Mat3 ds = edges_of(mesh.x, mesh.tets, t);
    const Eigen::FullPivLU<Mat3> lu(ds);
    if (!lu.isInvertible()) continue;
    const Vec3 w = lu.solve(p - row3(mesh.x, mesh.tets(t, 0)));
    if (w.minCoeff() >= 0 && w.sum() <= 1) inside = t;
  }
  const int t = inside >= 0 ? inside : nearest;
  if (t < 0) return std::nullopt;
  const Mat3 ds = edges_of(mesh.x, mesh.tets, t);
  const Mat3 dm = edges_of(mesh.rest, mesh.tets, t);
  const Real rest_volume = dm.determinant();
  if (!(ds.determinant() > min_volume_ratio * rest_volume)) return std::nullopt;
  MaterialMap map;
  map.tet = t;
  map.inside = inside >= 0;
  map.origin = row3(mesh.x, mesh.tets(t, 0));
  map.rest_origin = row3(mesh.rest, mesh.tets(t, 0));
  map.to_rest = dm * ds.inverse();
  return map;
}

bool tangled_near(const TetMesh& mesh, const Vec3& a, const Vec3& b, Real reach) {
  reach = std::max(Real(0), reach);
  const Vec3 d = b - a;
  // Whether the edge a + s d, s in [0, 1], meets the box [lo, hi] (the slabs, axis by axis).
  const auto meets = [&](const Vec3& lo, const Vec3& hi) {
    Real enter = 0, leave = 1;
    for (int k = 0; k < 3; ++k) {
      if (d[k] == 0) {
        if (a[k] < lo[k] || a[k] > hi[k]) return false;
        continue;
      }
      Real s0 = (lo[k] - a[k]) / d[k], s1 = (hi[k] - a[k]) / d[k];
      if (s0 > s1) std::swap(s0, s1);
      enter = std::max(enter, s0);
      leave = std::min(leave, s1);
      if (enter > leave) return false;
    }
    return true;
  };
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Real rest_volume = edges_of(mesh.rest, mesh.tets, t).determinant();
    if (edges_of(mesh.x, mesh.tets, t).determinant() * rest_volume > 0) continue;
    Vec3 lo = row3(mesh.x, mesh.tets(t, 0)), hi = lo;
    for (int k = 1; k < 4; ++k) {
      lo = lo.cwiseMin(row3(mesh.x, mesh.tets(t, k)));
      hi = hi.cwiseMax(row3(mesh.x, mesh.tets(t, k)));
    }
    if (meets((lo.array() - reach).matrix(), (hi.array() + reach).matrix())) return true;
  }
  return false;
}

}  // namespace incise::sim::cut
