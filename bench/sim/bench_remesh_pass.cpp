// The remeshing cost figures on a liver-sized organ, through AdaptiveBody (remesher, state transfer
// and the local model update together), for the corotational FEM and the mass-spring model, with
// refinement scanning every tet ("full scan") and with RefinementSettings::region ("region
// walk"):
//   - one insertion: refine with max_insertions = 1, called until the region is done (the call's
//     own search for bad tets, the insertion, its flips, the floor checks and the model update);
//   - one removal: decimate with max_attempts = 1, called until every inserted vertex is gone;
//   - one pass: a whole refinement of a 1 cm ball centred on the top of the organ to
//     circumradius 2.5 mm (l_min 1 mm) in one call, then the whole decimation in one call.
// Passes restore the mesh exactly (full decimation), so they are repeated and the median shown.
// Measures; asserts nothing. Run:
//   bench_remesh_pass [cell_size_m = 0.007] [passes = 5]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "sim/mesh/cgal/implicit_shape.h"
#include "sim/mesh/cgal/mesh_generation.h"
#include "sim/remesh/adaptive_body.h"
#include "sim/scene/scene_run.h"

using namespace incise::sim;
using namespace incise::sim::remesh;
using Clock = std::chrono::steady_clock;

namespace {

constexpr Real kBallRadius = 0.01;  // the tool region [m]
constexpr Real kTarget = 0.0025;    // target circumradius [m]
constexpr Real kLMin = 0.001;       // floor [m]

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The value below which the fraction q of the samples lie (nearest rank).
double quantile(std::vector<double> samples, double q) {
  if (samples.empty()) return 0;
  std::sort(samples.begin(), samples.end());
  const size_t rank = static_cast<size_t>(q * static_cast<double>(samples.size() - 1) + 0.5);
  return samples[std::min(rank, samples.size() - 1)];
}

struct Row {
  std::string model, mode;
  std::vector<double> insertion_ms, removal_ms, refine_pass_ms, decimate_pass_ms;
  int pass_insertions = 0;
  int pass_unresolved = 0;
  bool restored = true;
};

ModelFactory factory(MaterialModel model) {
  Scene scene;
  scene.material.model = model;
  scene.material.youngs_modulus = 3000;
  scene.material.poisson_ratio = 0.3;
  scene.material.density = 1000;
  scene.material.damping = 0.3;
  return [scene](const TetMesh& mesh) { return make_model(scene, mesh); };
}

Row measure(const TetMesh& organ, MaterialModel model, const char* model_name, bool hint,
            const Vec3& tool, int passes) {
  Row row{model_name, hint ? "region walk" : "full scan", {}, {}, {}, {}, 0, 0, true};
  AdaptiveBody body(organ, factory(model));
  const int original_vertices = body.num_vertices();
  const int original_tets = body.num_tets();
  const SizeField field = sphere_size_field(tool, kBallRadius, kTarget);
  const SizeField nowhere = [](const Vec3&) { return std::numeric_limits<Real>::infinity(); };
  RefinementSettings settings;
  settings.l_min = kLMin;
  if (hint) settings.region = region_hint_of(tool, kBallRadius);

  for (int pass = 0; pass < passes; ++pass) {
    auto start = Clock::now();
    const RefinementStats stats = body.refine(field, settings);
    row.refine_pass_ms.push_back(ms_since(start));
    row.pass_insertions = stats.insertions();
    row.pass_unresolved = stats.unresolved_size + stats.unresolved_quality;
    if (pass == 0) {
      std::printf(
          "%s, %s: in tet %d, on face %d, on edge %d, constraint splits %d, pulled back %d; "
          "refused: l_min %d, other %d; rolled back %d\n",
          model_name, row.mode.c_str(), stats.in_tet, stats.on_face, stats.on_edge,
          stats.constraint_splits, stats.pulled_back, stats.rejected_l_min, stats.rejected_other,
          stats.rolled_back);
    }
    start = Clock::now();
    body.decimate(nowhere, std::numeric_limits<int>::max());
    row.decimate_pass_ms.push_back(ms_since(start));
    row.restored = row.restored && body.num_vertices() == original_vertices &&
                   body.num_tets() == original_tets;
  }

  settings.max_insertions = 1;
  for (;;) {
    const auto start = Clock::now();
    const RefinementStats stats = body.refine(field, settings);
    const double ms = ms_since(start);
    if (stats.insertions() == 1) row.insertion_ms.push_back(ms);
    if (!stats.budget_exhausted) break;
  }
  for (int guard = 0; body.num_vertices() > original_vertices && guard < 100000; ++guard) {
    const auto start = Clock::now();
    const DecimationStats stats = body.decimate(nowhere, 1);
    const double ms = ms_since(start);
    if (stats.removed == 1) row.removal_ms.push_back(ms);
  }
  row.restored = row.restored && body.num_tets() == original_tets;
  if (!row.restored) {
    std::printf("%s, %s: after the last removal %d vertices (%d originally), %d tets (%d)\n",
                model_name, row.mode.c_str(), body.num_vertices(), original_vertices,
                body.num_tets(), original_tets);
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const Real cell = argc > 1 ? std::atof(argv[1]) : 0.007;
  const int passes = argc > 2 ? std::atoi(argv[2]) : 5;
  // A liver-sized organ (18 cm long), meshed as the scenes' "generate" source does.
  const ImplicitShape shape = liver_like_organ(Vec3::Zero(), 0.18);
  MeshingCriteria criteria;
  criteria.cell_size = cell;
  criteria.facet_size = cell;
  criteria.facet_distance = cell / 4;
  Box3 bounds = implicit_extent(shape);
  const Vec3 margin = 0.05 * bounds.sizes();
  bounds.extend(bounds.max() + margin);
  bounds.extend(bounds.min() - margin);
  auto start = Clock::now();
  const TetMesh organ = mesh_implicit(shape, bounds, criteria);
  std::printf("organ: 18 cm liver-like, cell %.4f m: %ld tets, %ld nodes (meshed in %.0f ms)\n",
              cell, static_cast<long>(organ.tets.rows()), static_cast<long>(organ.rest.rows()),
              ms_since(start));
  // The tool touches the top of the organ: the highest node, which lies on the surface.
  Eigen::Index top = 0;
  organ.rest.col(2).maxCoeff(&top);
  const Vec3 tool = organ.rest.row(top).transpose();
  std::printf(
      "tool ball: centre (%.4f, %.4f, %.4f) m, radius %.0f mm, target %.1f mm, "
      "l_min %.0f mm\n\n",
      tool.x(), tool.y(), tool.z(), kBallRadius * 1e3, kTarget * 1e3, kLMin * 1e3);

  std::vector<Row> rows;
  for (const bool hint : {false, true}) {
    rows.push_back(measure(organ, MaterialModel::corotational, "corotational", hint, tool, passes));
    rows.push_back(measure(organ, MaterialModel::mass_spring, "mass-spring", hint, tool, passes));
  }
  std::printf(
      "| model | search | insertion median / p99 [us] | removal median / p99 [us] | refine pass "
      "[ms] | decimate pass [ms] | insertions (unresolved) | pass fits 1 ms |\n"
      "|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const double refine = quantile(r.refine_pass_ms, 0.5);
    const double decimate = quantile(r.decimate_pass_ms, 0.5);
    std::printf(
        "| %s | %s | %.1f / %.1f (n=%zu) | %.1f / %.1f (n=%zu) | %.3f | %.3f | %d (%d) | "
        "%s |%s\n",
        r.model.c_str(), r.mode.c_str(), 1e3 * quantile(r.insertion_ms, 0.5),
        1e3 * quantile(r.insertion_ms, 0.99), r.insertion_ms.size(),
        1e3 * quantile(r.removal_ms, 0.5), 1e3 * quantile(r.removal_ms, 0.99), r.removal_ms.size(),
        refine, decimate, r.pass_insertions, r.pass_unresolved,
        refine <= 1.0 && decimate <= 1.0 ? "yes" : "no", r.restored ? "" : " (mesh NOT restored)");
  }
}
