#include "sim/remesh/adaptive_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sim/remesh/adaptation_regions.h"
#include "sim/remesh/adaptive_body.h"
#include "sim/remesh/time_step_floor.h"
#include "sim/scene/node_selection.h"
#include "sim/scene/scene_error.h"
#include "sim/scene/scene_validation.h"
#include "sim/solve/stable_time_step.h"

namespace incise::sim::remesh {
namespace {

AdaptationCriteria criteria_of(const AdaptivitySpec& spec, Real merge_distance) {
  constexpr Real kRadiansPerDegree = std::numbers::pi / 180;
  AdaptationCriteria c;
  c.strain = spec.strain;
  c.strain_on = spec.strain_on;
  c.strain_off = spec.strain_off;
  c.curvature = spec.curvature;
  c.bend_on = spec.bend_on_degrees * kRadiansPerDegree;
  c.bend_off = spec.bend_off_degrees * kRadiansPerDegree;
  c.fine_size = spec.fine_size;
  c.keep_margin = spec.keep_margin.value_or(spec.fine_size);
  c.merge_distance = merge_distance;
  return c;
}

bool in_box(const Box3& box, const Vec3& p, Real tolerance) {
  return (p.array() >= box.min().array() - tolerance).all() &&
         (p.array() <= box.max().array() + tolerance).all();
}

// The bounding-box diagonal of the alive vertices' positions [m]. Dead slots are parked at their
// rest points and would count the rest box in.
Real alive_diagonal(const AdaptiveBody& body) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity());
  Vec3 hi = -lo;
  for (int i = 0; i < body.num_vertex_slots(); ++i) {
    if (!body.mesh().vertex_alive(i)) continue;
    const Vec3 p = body.x().row(i).transpose();
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto middle = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  return *middle;
}

// The scene's loads as external forces per vertex slot: each load's force split equally over
// the alive vertices whose rest point lies in its box.
void resolve_loads(const Scene& scene, const AdaptiveBody& body, Real tolerance, Points& external,
                   std::vector<int>& scratch) {
  external.setZero(body.num_vertex_slots(), 3);
  for (std::size_t l = 0; l < scene.loads.size(); ++l) {
    scratch.clear();
    for (int i = 0; i < body.num_vertex_slots(); ++i) {
      if (body.mesh().vertex_alive(i) &&
          in_box(scene.loads[l].where.box, body.mesh().point(i), tolerance)) {
        scratch.push_back(i);
      }
    }
    // Original vertices are never removed, so a load that selected a node at the start always
    // does; this guards the start.
    if (scratch.empty()) {
      throw SceneError("loads[" + std::to_string(l) + "].where.box", "selects no node");
    }
    const Vec3 share = scene.loads[l].force / static_cast<Real>(scratch.size());
    for (const int i : scratch)
      external.row(i) += share.transpose();
  }
}

// The tet across each face per tet slot (-1 on the boundary; rows of dead slots unused), for
// the curvature criterion.
void slot_neighbors(const RemeshMesh& mesh, Tets& neighbors) {
  neighbors.resize(mesh.num_tet_slots(), 4);
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    for (int k = 0; k < 4; ++k)
      neighbors(t, k) = mesh.tet_alive(t) ? mesh.neighbor(t, k) : -1;
  }
}

}  // namespace

CheckedRun run_adaptive_scene(const Scene& scene, TetMesh mesh, TetMesh* final_mesh) {
  validate_scene(scene);
  if (!scene.adaptivity) throw SceneError("adaptivity", "is not set");
  if (mesh.num_tets() == 0) throw SceneError("mesh", "has no tetrahedra");
  const AdaptivitySpec& spec = *scene.adaptivity;
  mesh.x.resize(0, 3);
  mesh.v.resize(0, 3);

  const Real tolerance = selection_tolerance(mesh.rest);
  for (std::size_t c = 0; c < scene.constraints.size(); ++c) {
    if (nodes_in_box(mesh.rest, scene.constraints[c].where.box, tolerance).empty()) {
      throw SceneError("constraints[" + std::to_string(c) + "].where.box", "selects no node");
    }
  }

  std::optional<AdaptiveBody> made;
  try {
    made.emplace(mesh, [&scene](const TetMesh& m) { return make_model(scene, m); });
  } catch (const std::invalid_argument& error) {
    throw SceneError("mesh", error.what());
  }
  AdaptiveBody& body = *made;
  // Constraints are "fix": "xyz" (validate_scene): a vertex is held if its rest point is in a box.
  std::vector<Box3> clamps;
  for (const Constraint& c : scene.constraints)
    clamps.push_back(c.where.box);
  body.set_fixed([clamps, tolerance](const Vec3& p) {
    return std::any_of(clamps.begin(), clamps.end(),
                       [&](const Box3& box) { return in_box(box, p, tolerance); });
  });

  RefinementSettings settings;
  settings.l_min =
      spec.dt_min > 0 ? l_min_for_dt_min(spec.dt_min, fastest_wave_speed(scene)) : spec.l_min;
  settings.max_radius_edge_ratio = spec.quality;
  // The floor's promise is on the stable step, which follows the smallest altitude.
  settings.floor_altitudes = true;
  // Decimation fills are held to the same floor, or to the start mesh's own smallest altitude
  // where that is lower (full decimation must be able to return to it).
  const TetMesh start = body.to_tet_mesh();
  body.set_decimation_floor(
      std::min(settings.l_min, element_lengths(start.rest, start.tets).min_altitude));
  // Hot tets within the start mesh's longest edge of a region's centre join it, so that a
  // strained zone makes a few balls rather than one per tet (update cost O(#tets x #balls)).
  Real longest_edge = 0;
  for (Eigen::Index t = 0; t < mesh.tets.rows(); ++t) {
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        longest_edge = std::max(
            longest_edge, (mesh.rest.row(mesh.tets(t, a)) - mesh.rest.row(mesh.tets(t, b))).norm());
      }
    }
  }
  AdaptationRegions regions(criteria_of(spec, longest_edge));

  Points external;
  std::vector<int> scratch;
  resolve_loads(scene, body, tolerance, external, scratch);
  Tets neighbors;

  const std::int64_t steps = scene.solver.steps;
  const Real dt = scene.solver.dt;
  CheckedRun checked;
  RunResult& result = checked.result;
  const Real rest_diagonal = alive_diagonal(body);
  std::vector<double> step_ms;
  step_ms.reserve(static_cast<std::size_t>(std::min(steps, kMaxTimedSteps)));
  const std::int64_t stride = (steps + kMaxTimedSteps - 1) / kMaxTimedSteps;

  for (std::int64_t n = 0; n < steps; ++n) {
    const auto start = std::chrono::steady_clock::now();
    body.step(dt, scene.gravity, external);
    result.finite = body.x().allFinite() && body.v().allFinite();
    if (result.finite && (n + 1) % spec.every == 0 && n + 1 < steps) {
      if (spec.curvature) slot_neighbors(body.mesh(), neighbors);
      regions.update(body.slot_view().rest, body.x(), body.slot_view().tets, neighbors,
                     body.tet_alive(), {});
      settings.region = regions.refine_hint();  // search only near the balls
      body.refine(regions.refine_field(), settings);
      body.decimate(regions.keep_field(), kDecimationAttempts);
      resolve_loads(scene, body, tolerance, external, scratch);
    }
    if (n % stride == 0) {
      step_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count());
    }
    ++result.steps;
    if (!continue_checked_run(n, result.finite ? alive_diagonal(body) / rest_diagonal : 0,
                              checked)) {
      break;
    }
  }
  if (!result.finite) --result.steps;  // the steps before the one that failed

  TetMesh final_state = body.to_tet_mesh();
  result.ms_per_step = median(std::move(step_ms));
  result.rest = final_state.rest;
  result.displacement = final_state.x - final_state.rest;
  result.num_tets = final_state.num_tets();
  result.max_speed = final_state.v.rowwise().norm().maxCoeff();
  result.inverted_elements = body.model().health().inverted_elements;
  result.final_positions = final_state.x;
  result.status = checked.status;
  if (final_mesh != nullptr) *final_mesh = std::move(final_state);
  return checked;
}

}  // namespace incise::sim::remesh
