// Size and quality control: refinement of a region to a target size under the l_min floor, on
// the meshes of the core's tests, checked against every invariant of the core; then decimation of
// everything inserted, which must give back the initial mesh exactly.

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "remesh_fixtures.h"
#include "sim/mesh/box_mesher.h"
#include "sim/remesh/decimation.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/point_location.h"
#include "sim/remesh/refinement.h"
#include "sim/remesh/region_quality.h"
#include "sim/remesh/remesh_validity.h"
#include "sim/remesh/tet_shape.h"

namespace incise::sim::remesh {
namespace {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

std::map<int, Real> volume_by_label(const RemeshMesh& mesh) {
  std::map<int, Real> volume;
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const TetVertices& v = mesh.tet(t);
    const Vec3 a = mesh.point(v[0]);
    volume[mesh.label(t)] +=
        (mesh.point(v[1]) - a).dot((mesh.point(v[2]) - a).cross(mesh.point(v[3]) - a)) / 6;
  }
  return volume;
}

// The smallest distance between two alive vertices of which at least one was inserted.
Real closest_inserted_pair(const RemeshMesh& mesh) {
  Real closest = kInfinity;
  for (int u = mesh.num_original_vertices(); u < mesh.num_vertex_slots(); ++u) {
    if (!mesh.vertex_alive(u)) continue;
    for (int w = 0; w < mesh.num_vertex_slots(); ++w) {
      if (w != u && mesh.vertex_alive(w)) {
        closest = std::min(closest, (mesh.point(u) - mesh.point(w)).norm());
      }
    }
  }
  return closest;
}

void decimate_all(RemeshMesh& mesh) {
  Decimator decimator;
  const SizeField nowhere = [](const Vec3&) { return kInfinity; };
  decimator.collect(mesh, nowhere);
  while (decimator.pending() > 0) {
    const DecimationStats stats = decimator.step(mesh, nowhere, 50);
    ASSERT_FALSE(stats.stuck);
  }
}

struct Case {
  const char* name;
  TetMesh mesh;
};

std::vector<Case> cases() {
  return {{"unit box", testing::unit_box()},
          {"two-label box", testing::two_label_box()},
          {"jittered two-label box", testing::jittered_two_label_box(3)}};
}

// A box region across the middle of the unit box (and across the label interface at x = 0.5)
// refined to circumradius 0.1 (cells are 0.25 wide, their tets' circumradii about 0.2). l_min is
// below the input's own smallest feature (the jittered box has a vertex 0.025 from its
// interface); a larger one leaves the flat tets there unresolved (FloorWinsOverTargetSize).
TEST(Refinement, BoxRegionReachesTargetSizeAndQualityAboveTheFloor) {
  const Real target = 0.1, l_min = 0.02, bound = 2.0;
  const SizeField field = box_size_field(Box3(Vec3(0.3, 0.3, 0.3), Vec3(0.7, 0.7, 0.7)), target);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    RemeshMesh mesh(c.mesh);
    make_constrained_delaunay(mesh);
    const auto initial = canonical_tets(mesh);
    const auto labels_volume = volume_by_label(mesh);
    RefinementSettings settings;
    settings.l_min = l_min;
    settings.max_radius_edge_ratio = bound;
    const RefinementStats stats = refine(mesh, field, settings);
    EXPECT_GT(stats.insertions(), 50);
    EXPECT_EQ(stats.floor_violations, 0);
    EXPECT_FALSE(stats.budget_exhausted);
    ASSERT_EQ(check_remesh_mesh(mesh), "");
    // The surface and the label interface are kept: each label's volume is unchanged.
    for (const auto& [label, volume] : volume_by_label(mesh))
      EXPECT_NEAR(volume, labels_volume.at(label), 1e-12) << "label " << label;
    // Size and quality reached everywhere in the region.
    const RegionQuality q = region_quality(mesh, field);
    EXPECT_EQ(stats.unresolved_size, 0);
    EXPECT_EQ(stats.unresolved_quality, 0);
    EXPECT_LE(q.max_size_ratio, 1.0);
    EXPECT_LE(q.max_radius_edge_ratio, bound);
    // The floor: no two vertices closer than l_min once one of them was inserted, so no edge
    // refinement created is shorter.
    EXPECT_GE(closest_inserted_pair(mesh), l_min);
    EXPECT_GE(shortest_inserted_edge(mesh), l_min);
    std::printf(
        "  %s: %d insertions (%d on constraints), %d refused by l_min, %d rolled back; "
        "region %d tets, ratio <= %.3f, min dihedral %.2f deg, min edge %.4f, min "
        "altitude %.4f\n",
        c.name, stats.insertions(), stats.constraint_splits, stats.rejected_l_min,
        stats.rolled_back, q.num_tets, q.max_radius_edge_ratio, q.min_dihedral * 180 / M_PI,
        q.min_edge, q.min_altitude);
    decimate_all(mesh);
    EXPECT_EQ(check_remesh_mesh(mesh), "");
    EXPECT_EQ(canonical_tets(mesh), initial);
  }
}

// A target below what l_min allows: the floor wins, some tets stay too large, and each call
// says how many; none of the vertices is closer than l_min to another.
TEST(Refinement, FloorWinsOverTargetSize) {
  const Real l_min = 0.06;
  const SizeField field = sphere_size_field(Vec3(0.5, 0.5, 0.5), 0.2, 0.02);
  RemeshMesh mesh(testing::jittered_two_label_box(5));
  make_constrained_delaunay(mesh);
  RefinementSettings settings;
  settings.l_min = l_min;
  const RefinementStats stats = refine(mesh, field, settings);
  EXPECT_GT(stats.rejected_l_min, 0);
  EXPECT_GT(stats.unresolved_size, 0);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  EXPECT_GE(closest_inserted_pair(mesh), l_min);
  // What is left too large is exactly what the stats say.
  int too_large = 0;
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const TetVertices& v = mesh.tet(t);
    const Vec3 &a = mesh.point(v[0]), &b = mesh.point(v[1]), &c = mesh.point(v[2]),
               &d = mesh.point(v[3]);
    if (in_region(field, a, b, c, d) && tet_shape(a, b, c, d).circumradius > 0.02) ++too_large;
  }
  EXPECT_EQ(too_large, stats.unresolved_size);
}

// With floor_altitudes, every tet with an inserted vertex is at least l_min high, the length
// stable_time_step measures.
TEST(Refinement, AltitudeFloor) {
  const Real l_min = 0.03;
  const SizeField field = box_size_field(Box3(Vec3(0.2, 0.2, 0.2), Vec3(0.8, 0.8, 0.8)), 0.1);
  RemeshMesh mesh(testing::jittered_two_label_box(7));
  make_constrained_delaunay(mesh);
  RefinementSettings settings;
  settings.l_min = l_min;
  settings.floor_altitudes = true;
  const RefinementStats stats = refine(mesh, field, settings);
  EXPECT_GT(stats.insertions(), 20);
  EXPECT_EQ(stats.floor_violations, 0);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const TetVertices& v = mesh.tet(t);
    bool inserted = false;
    for (int k = 0; k < 4; ++k)
      inserted = inserted || !mesh.is_original(v[k]);
    if (!inserted) continue;
    EXPECT_GE(tet_shape(mesh.point(v[0]), mesh.point(v[1]), mesh.point(v[2]), mesh.point(v[3]))
                  .min_altitude,
              l_min)
        << "tet " << t;
  }
}

// A budget of a few insertions per call: calls carry on where the last stopped and end where a
// single call does.
TEST(Refinement, BoundedWorkPerCall) {
  const SizeField field = sphere_size_field(Vec3(0.5, 0.5, 0.5), 0.3, 0.1);
  RefinementSettings settings;
  settings.l_min = 0.02;
  RemeshMesh once(testing::two_label_box());
  make_constrained_delaunay(once);
  const RefinementStats all = refine(once, field, settings);
  ASSERT_EQ(all.unresolved_size, 0);
  RemeshMesh mesh(testing::two_label_box());
  make_constrained_delaunay(mesh);
  settings.max_insertions = 7;
  int calls = 0;
  for (;; ++calls) {
    const RefinementStats stats = refine(mesh, field, settings);
    EXPECT_LE(stats.insertions(), 7);
    if (!stats.budget_exhausted) {
      EXPECT_EQ(stats.unresolved_size, 0);
      break;
    }
  }
  EXPECT_GE(calls, all.insertions() / 7 - 1);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  EXPECT_LE(region_quality(mesh, field).max_size_ratio, 1.0);
}

TEST(Refinement, RejectsBadSettings) {
  RemeshMesh mesh(testing::unit_box());
  const SizeField field = sphere_size_field(Vec3(0.5, 0.5, 0.5), 0.3, 0.1);
  RefinementSettings settings;
  EXPECT_THROW(refine(mesh, field, settings), std::invalid_argument);  // l_min = 0
  settings.l_min = 0.01;
  settings.max_radius_edge_ratio = 0.5;
  EXPECT_THROW(refine(mesh, field, settings), std::invalid_argument);
  settings.max_radius_edge_ratio = 2;
  EXPECT_THROW(refine(mesh, SizeField{}, settings), std::invalid_argument);
  EXPECT_THROW(box_size_field(Box3(Vec3::Zero(), Vec3::Ones()), 0), std::invalid_argument);
  EXPECT_THROW(sphere_size_field(Vec3::Zero(), -1, 0.1), std::invalid_argument);
  settings.region = RegionHint{Vec3::Zero(), -1};
  EXPECT_THROW(refine(mesh, field, settings), std::invalid_argument);
  settings.region = RegionHint{Vec3(kInfinity, 0, 0), 1};
  EXPECT_THROW(refine(mesh, field, settings), std::invalid_argument);
  EXPECT_THROW(region_hint_of(Vec3::Zero(), -0.1), std::invalid_argument);
  EXPECT_THROW(region_hint_of(Box3()), std::invalid_argument);
}

// What a refinement call did, for comparing two runs: the stats, the inserted and removed
// vertices in order (with their rest points), and the resulting tets.
struct RefinementTrace {
  RefinementStats stats;
  std::vector<std::pair<int, Vec3>> inserted;
  std::vector<int> removed;
  decltype(canonical_tets(std::declval<const RemeshMesh&>())) tets;
  long field_calls = 0;
};

RefinementTrace traced_refine(const TetMesh& input, const SizeField& field,
                              const RefinementSettings& settings) {
  RemeshMesh mesh(input);
  make_constrained_delaunay(mesh);
  RefinementTrace trace;
  RemeshListener listener;
  listener.on_inserted = [&](const InsertedVertex& v, const TetChanges&) {
    trace.inserted.emplace_back(v.vertex, v.rest_point);
  };
  listener.on_removal = [&](int v, const RemoveResult&) { trace.removed.push_back(v); };
  const SizeField counted = [&](const Vec3& p) {
    ++trace.field_calls;
    return field(p);
  };
  trace.stats = refine(mesh, counted, settings, listener);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  trace.tets = canonical_tets(mesh);
  return trace;
}

void expect_same_run(const RefinementTrace& full, const RefinementTrace& local) {
  EXPECT_EQ(local.stats.insertions(), full.stats.insertions());
  EXPECT_EQ(local.stats.constraint_splits, full.stats.constraint_splits);
  EXPECT_EQ(local.stats.rejected_l_min, full.stats.rejected_l_min);
  EXPECT_EQ(local.stats.rejected_other, full.stats.rejected_other);
  EXPECT_EQ(local.stats.rolled_back, full.stats.rolled_back);
  EXPECT_EQ(local.stats.unresolved_size, full.stats.unresolved_size);
  EXPECT_EQ(local.stats.unresolved_quality, full.stats.unresolved_quality);
  EXPECT_EQ(local.stats.budget_exhausted, full.stats.budget_exhausted);
  ASSERT_EQ(local.inserted.size(), full.inserted.size());
  for (size_t i = 0; i < full.inserted.size(); ++i) {
    EXPECT_EQ(local.inserted[i].first, full.inserted[i].first) << "insertion " << i;
    EXPECT_EQ(local.inserted[i].second, full.inserted[i].second) << "insertion " << i;
  }
  EXPECT_EQ(local.removed, full.removed);
  EXPECT_EQ(local.tets, full.tets);
}

// With RefinementSettings::region, refinement visits only the tets near the region and does
// exactly what the scan of every tet does: same points inserted in the same order into the same
// slots, same refusals and roll-backs, same final tets, on the three fixtures and for regions
// inside the body, across the label interface, centred on the surface, centred outside the body
// (the walk stops at the surface and descends to the ball) and at a corner; also with a budget.
TEST(Refinement, RegionHintGivesTheSameRunAsTheFullScan) {
  struct Region {
    const char* name;
    SizeField field;
    RegionHint hint;
  };
  const Box3 middle(Vec3(0.3, 0.3, 0.3), Vec3(0.7, 0.7, 0.7));
  const std::vector<Region> regions = {
      {"middle box", box_size_field(middle, 0.1), region_hint_of(middle)},
      {"ball on the top", sphere_size_field(Vec3(0.5, 0.5, 1), 0.3, 0.08),
       region_hint_of(Vec3(0.5, 0.5, 1), 0.3)},
      {"ball centred outside", sphere_size_field(Vec3(0.4, 0.6, 1.15), 0.35, 0.08),
       region_hint_of(Vec3(0.4, 0.6, 1.15), 0.35)},
      {"corner ball", sphere_size_field(Vec3(0, 0, 0), 0.3, 0.06),
       region_hint_of(Vec3(0, 0, 0), 0.3)}};
  for (const Case& c : cases()) {
    for (const Region& r : regions) {
      for (const int budget : {std::numeric_limits<int>::max(), 5}) {
        SCOPED_TRACE(std::string(c.name) + ", " + r.name + ", budget " + std::to_string(budget));
        RefinementSettings settings;
        settings.l_min = 0.03;
        settings.max_insertions = budget;
        const RefinementTrace full = traced_refine(c.mesh, r.field, settings);
        settings.region = r.hint;
        const RefinementTrace local = traced_refine(c.mesh, r.field, settings);
        EXPECT_GT(full.stats.insertions(), 0);
        expect_same_run(full, local);
      }
    }
  }
}

// On a larger mesh the hinted call asks the size field about the tets near the ball only (each
// considered tet costs one call), where the full scan asks about every tet, twice.
TEST(Refinement, RegionHintVisitsOnlyTetsNearTheRegion) {
  const TetMesh box = make_box_mesh(Vec3(1, 1, 1), Vec3i(12, 12, 12));  // 10,368 tets
  const Vec3 center(0.5, 0.5, 1);
  const SizeField field = sphere_size_field(center, 0.1, 0.03);
  RefinementSettings settings;
  settings.l_min = 0.01;
  const RefinementTrace full = traced_refine(box, field, settings);
  settings.region = region_hint_of(center, 0.1);
  const RefinementTrace local = traced_refine(box, field, settings);
  expect_same_run(full, local);
  EXPECT_GE(full.field_calls, 2 * 10368);
  // Both runs ask the same for the tets refinement creates; the region walk then asks only about
  // the tets near the ball (a few hundred, twice) instead of all 10,368 and more, twice.
  EXPECT_LT(5 * local.field_calls, full.field_calls);
  std::printf("  field calls: full scan %ld, region walk %ld, %d insertions\n", full.field_calls,
              local.field_calls, local.stats.insertions());
}

// The walk finds the tet holding a point from any start, and stops at the surface for a point
// outside the body.
TEST(PointLocation, WalkFindsContainingTetOrStopsAtSurface) {
  RemeshMesh mesh(testing::jittered_two_label_box(11));
  make_constrained_delaunay(mesh);
  const Vec3 inside(0.37, 0.61, 0.23);
  for (int start = 0; start < mesh.num_tet_slots(); start += 17) {
    const Location where = locate(mesh, start, inside);
    ASSERT_NE(where.kind, LocationKind::kNotFound);
    if (where.kind == LocationKind::kBeyondConstraint) {
      // Stopped at the label interface x = 0.5 between start and the point.
      EXPECT_GE(mesh.face_parent(where.tet, where.face), 0);
      continue;
    }
    EXPECT_EQ(where.kind, LocationKind::kInTet);
    const TetVertices& v = mesh.tet(where.tet);
    const Vec3 a = mesh.point(v[0]);
    const Mat3 edges =
        (Mat3() << mesh.point(v[1]) - a, mesh.point(v[2]) - a, mesh.point(v[3]) - a).finished();
    const Vec3 w = edges.inverse() * (inside - a);
    EXPECT_GE(w.minCoeff(), -1e-12);
    EXPECT_LE(w.sum(), 1 + 1e-12);
  }
  int right = 0;  // a tet on the x > 0.5 side of the interface, so that only the surface is left
  while (mesh.label(right) != 1)
    ++right;
  const Location outside = locate(mesh, right, Vec3(1.5, 0.5, 0.5));
  EXPECT_EQ(outside.kind, LocationKind::kBeyondConstraint);
  EXPECT_LT(mesh.neighbor(outside.tet, outside.face), 0);
}

}  // namespace
}  // namespace incise::sim::remesh
