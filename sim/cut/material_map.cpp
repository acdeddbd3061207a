#include "sim/cut/material_map.h"

#include <algorithm>
#include <cmath>

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
  // The edge sampled at reach / 2: a box grown by reach that the edge passes through holds one of
  // the samples.
  const int samples = 1 + static_cast<int>(std::ceil((b - a).norm() / (0.5 * reach)));
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Real rest_volume = edges_of(mesh.rest, mesh.tets, t).determinant();
    if (edges_of(mesh.x, mesh.tets, t).determinant() * rest_volume > 0) continue;
    Vec3 lo = row3(mesh.x, mesh.tets(t, 0)), hi = lo;
    for (int k = 1; k < 4; ++k) {
      lo = lo.cwiseMin(row3(mesh.x, mesh.tets(t, k)));
      hi = hi.cwiseMax(row3(mesh.x, mesh.tets(t, k)));
    }
    lo.array() -= reach;
    hi.array() += reach;
    for (int s = 0; s < samples; ++s) {
      const Vec3 p = a + (static_cast<Real>(s) / std::max(1, samples - 1)) * (b - a);
      if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) return true;
    }
  }
  return false;
}

}  // namespace incise::sim::cut
