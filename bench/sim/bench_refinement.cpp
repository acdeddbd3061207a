// Cost of a whole refinement pass around a tool and of decimating it again, on a liver-sized
// box (15 x 10 x 8 cm, 1 cm cells, 7,200 tets): a ball of 1 cm radius at the middle of the top
// surface refined to circumradius 2.5 mm with l_min = 1 mm. Measures; asserts nothing. Run:
//   bench_refinement

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "sim/mesh/box_mesher.h"
#include "sim/remesh/decimation.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/refinement.h"
#include "sim/remesh/region_quality.h"
#include "sim/remesh/remesh_validity.h"

using namespace incise::sim;
using namespace incise::sim::remesh;
using Clock = std::chrono::steady_clock;

int main() {
  RemeshMesh mesh(make_box_mesh(Vec3(0.15, 0.10, 0.08), Vec3i(15, 10, 8)));
  const int frozen = make_constrained_delaunay(mesh);
  const auto initial = canonical_tets(mesh);
  std::printf("mesh: %d tets, %d vertices, %d frozen faces\n", mesh.num_tets(), mesh.num_vertices(),
              frozen);
  const SizeField field = sphere_size_field(Vec3(0.075, 0.05, 0.08), 0.01, 0.0025);
  RefinementSettings settings;
  settings.l_min = 0.001;
  auto start = Clock::now();
  const RefinementStats stats = refine(mesh, field, settings);
  const double refine_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  const RegionQuality q = region_quality(mesh, field);
  std::printf(
      "refine: %.2f ms, %d insertions (%d on constraints, %d pulled back), %d refused "
      "(l_min), %d refused (other), %d rolled back -> %d tets\n",
      refine_ms, stats.insertions(), stats.constraint_splits, stats.pulled_back,
      stats.rejected_l_min, stats.rejected_other, stats.rolled_back, mesh.num_tets());
  std::printf(
      "region: %d tets, circumradius/target <= %.3f, radius-edge <= %.3f, dihedral "
      "%.2f..%.2f deg, min edge %.3f mm, min altitude %.3f mm; unresolved %d size %d "
      "quality\n",
      q.num_tets, q.max_size_ratio, q.max_radius_edge_ratio, q.min_dihedral * 180 / M_PI,
      q.max_dihedral * 180 / M_PI, q.min_edge * 1e3, q.min_altitude * 1e3, stats.unresolved_size,
      stats.unresolved_quality);
  std::printf("valid: %s\n", check_remesh_mesh(mesh).empty() ? "yes" : "NO");
  Decimator decimator;
  const SizeField nowhere = [](const Vec3&) { return std::numeric_limits<Real>::infinity(); };
  start = Clock::now();
  decimator.collect(mesh, nowhere);
  int removed = 0;
  while (decimator.pending() > 0)
    removed += decimator.step(mesh, nowhere, 100).removed;
  const double decimate_ms =
      std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  std::printf("decimate: %.2f ms for %d removals; initial mesh back: %s\n", decimate_ms, removed,
              canonical_tets(mesh) == initial ? "yes" : "NO");
}
