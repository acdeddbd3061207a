#include "collide_fixtures.h"

#include <cmath>
#include <numbers>
#include <random>

#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"

namespace incise::sim::collide::testing {

TestSurface deformed_box_surface(const Vec3& size, const Vec3i& cells, Real jitter, unsigned seed) {
  const TetMesh mesh = make_box_mesh(size, cells);
  const BoundarySurface surface = boundary_surface(mesh);
  TestSurface out;
  Points normals;
  surface_vertices(surface, mesh.x, out.points, normals);
  out.triangles = surface.faces;
  std::mt19937 random(seed);
  std::uniform_real_distribution<Real> uniform(-jitter, jitter);
  for (int i = 0; i < out.points.rows(); ++i) {
    const Vec3 p = row3(out.points, i);
    // A bend: the top sags in the middle, as under a probe.
    const Real sag = 0.1 * size.z() * std::sin(std::numbers::pi * p.x() / size.x()) *
                     std::sin(std::numbers::pi * p.y() / size.y()) * p.z() / size.z();
    out.points.row(i) += Vec3(uniform(random), uniform(random), uniform(random) - sag).transpose();
  }
  return out;
}

TestSurface jittered_sphere_surface(const Vec3& centre, Real radius, int rings, int segments,
                                    Real jitter, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<Real> uniform(-jitter, jitter);
  TestSurface out;
  const int num_points = rings * segments + 2;
  out.points.resize(num_points, 3);
  const auto put = [&](int i, Real theta, Real phi) {
    const Vec3 direction(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         std::cos(theta));
    out.points.row(i) = (centre + radius * (1 + uniform(random)) * direction).transpose();
  };
  const int north = rings * segments;
  const int south = north + 1;
  put(north, 0, 0);
  put(south, std::numbers::pi, 0);
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      put(r * segments + s, std::numbers::pi * (r + 1) / (rings + 1),
          2 * std::numbers::pi * s / segments);
    }
  }
  out.triangles.resize(2 * segments * rings, 3);
  int t = 0;
  const auto id = [&](int r, int s) { return r * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    out.triangles.row(t++) << north, id(0, s), id(0, s + 1);
    out.triangles.row(t++) << south, id(rings - 1, s + 1), id(rings - 1, s);
  }
  for (int r = 0; r + 1 < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      out.triangles.row(t++) << id(r, s), id(r + 1, s), id(r + 1, s + 1);
      out.triangles.row(t++) << id(r, s), id(r + 1, s + 1), id(r, s + 1);
    }
  }
  return out;
}

TestSurface flat_sheet(Real half, int n, Real z) {
  TestSurface out;
  out.points.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      out.points.row(i + (n + 1) * j) << -half + 2 * half * i / n, -half + 2 * half * j / n, z;
    }
  }
  out.triangles.resize(2 * n * n, 3);
  int t = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int v00 = i + (n + 1) * j;
      const int v10 = v00 + 1;
      const int v01 = v00 + n + 1;
      const int v11 = v01 + 1;
      out.triangles.row(t++) << v00, v10, v11;
      out.triangles.row(t++) << v00, v11, v01;
    }
  }
  return out;
}

TestSurface box_hull(const Vec3& lo, const Vec3& hi) {
  TestSurface out;
  out.points.resize(8, 3);
  for (int k = 0; k < 8; ++k) {
    out.points.row(k) << (k & 1 ? hi.x() : lo.x()), (k & 2 ? hi.y() : lo.y()),
        (k & 4 ? hi.z() : lo.z());
  }
  // Each face as a quad (counter-clockwise seen from outside), split into two triangles.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  out.triangles.resize(12, 3);
  for (int f = 0; f < 6; ++f) {
    out.triangles.row(2 * f) << quads[f][0], quads[f][1], quads[f][2];
    out.triangles.row(2 * f + 1) << quads[f][0], quads[f][2], quads[f][3];
  }
  return out;
}

}  // namespace incise::sim::collide::testing
