// The decimation driver: only inserted vertices outside the kept region are removed, the work per
// call is bounded, and a vertex that cannot be removed now is retried later until all are gone.

#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "remesh_fixtures.h"
#include "sim/remesh/decimation.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/refinement.h"
#include "sim/remesh/remesh_validity.h"
#include "sim/remesh/tet_shape.h"

namespace incise::sim::remesh {
namespace {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

// The jittered two-label box refined in a ball around its centre.
RemeshMesh refined_box() {
  RemeshMesh mesh(testing::jittered_two_label_box(21));
  make_constrained_delaunay(mesh);
  RefinementSettings settings;
  settings.l_min = 0.04;
  refine(mesh, sphere_size_field(Vec3(0.5, 0.5, 0.5), 0.35, 0.1), settings);
  return mesh;
}

int inserted_count(const RemeshMesh& mesh) {
  return mesh.num_vertices() - mesh.num_original_vertices();
}

// Removal that refuses each vertex the first `refusals` times it is asked, leaving the mesh as
// it is, like kCannotRemoveNow does.
Decimator::RemoveFunction refusing(int refusals, std::map<int, int>* asked) {
  return [refusals, asked](RemeshMesh& mesh, int v) {
    if ((*asked)[v]++ < refusals) return RemoveResult{RemoveStatus::kCannotRemoveNow, {}};
    return remove_vertex(mesh, v);
  };
}

TEST(Decimation, RemovesOnlyOutsideTheKeptRegion) {
  RemeshMesh mesh = refined_box();
  ASSERT_GT(inserted_count(mesh), 20);
  const SizeField keep = box_size_field(Box3(Vec3(0, 0, 0), Vec3(0.5, 1, 1)), 0.1);
  Decimator decimator;
  const int queued = decimator.collect(mesh, keep);
  EXPECT_GT(queued, 0);
  EXPECT_LT(queued, inserted_count(mesh));
  EXPECT_EQ(decimator.collect(mesh, keep), 0);  // already queued
  int removed = 0;
  while (decimator.pending() > 0)
    removed += decimator.step(mesh, keep, 1000).removed;
  EXPECT_EQ(removed, queued);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  for (int v = mesh.num_original_vertices(); v < mesh.num_vertex_slots(); ++v) {
    if (mesh.vertex_alive(v)) {
      EXPECT_LE(mesh.point(v).x(), 0.5) << "vertex " << v;
    }
  }
}

// Every vertex refused twice before it goes: bounded calls of 5 attempts, each refusal queued at
// the back, and in the end all removed and the initial mesh back exactly.
TEST(Decimation, RetryQueueEventuallyRemovesAll) {
  RemeshMesh mesh = refined_box();
  RemeshMesh fresh(testing::jittered_two_label_box(21));
  make_constrained_delaunay(fresh);
  const int inserted = inserted_count(mesh);
  std::map<int, int> asked;
  Decimator decimator(refusing(2, &asked));
  const SizeField nowhere = [](const Vec3&) { return kInfinity; };
  EXPECT_EQ(decimator.collect(mesh, nowhere), inserted);
  int removed = 0, deferred = 0;
  RemeshListener listener;
  int reported_removals = 0;
  listener.on_removal = [&](int, const RemoveResult& r) {
    reported_removals += r.status == RemoveStatus::kRemoved;
  };
  while (decimator.pending() > 0) {
    const DecimationStats stats = decimator.step(mesh, nowhere, 5, listener);
    EXPECT_LE(stats.removed + stats.deferred, 5);
    EXPECT_FALSE(stats.stuck);
    removed += stats.removed;
    deferred += stats.deferred;
  }
  EXPECT_EQ(removed, inserted);
  EXPECT_EQ(reported_removals, inserted);
  EXPECT_EQ(deferred, 2 * inserted);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  EXPECT_EQ(canonical_tets(mesh), canonical_tets(fresh));
}

// Nothing removable now: the call stops after one round of refusals instead of spinning, and the
// vertices stay queued.
TEST(Decimation, StopsWhenStuck) {
  RemeshMesh mesh = refined_box();
  const auto before = canonical_tets(mesh);
  Decimator decimator([](RemeshMesh&, int) {
    return RemoveResult{RemoveStatus::kCannotRemoveNow, {}};
  });
  const SizeField nowhere = [](const Vec3&) { return kInfinity; };
  const int queued = decimator.collect(mesh, nowhere);
  const DecimationStats stats = decimator.step(mesh, nowhere, 1 << 20);
  EXPECT_TRUE(stats.stuck);
  EXPECT_EQ(stats.deferred, queued);
  EXPECT_EQ(decimator.pending(), queued);
  EXPECT_EQ(canonical_tets(mesh), before);
  EXPECT_THROW(decimator.step(mesh, nowhere, -1), std::invalid_argument);
}

// The smallest altitude over the alive tets.
Real min_altitude(const RemeshMesh& mesh) {
  Real lowest = kInfinity;
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const TetVertices& v = mesh.tet(t);
    lowest = std::min(
        lowest, tet_shape(mesh.point(v[0]), mesh.point(v[1]), mesh.point(v[2]), mesh.point(v[3]))
                    .min_altitude);
  }
  return lowest;
}

// Refinement under floor_altitudes, then decimation of a moving region, `rounds` times; returns
// the lowest altitude seen after any decimation call, and counts the vertices left behind.
Real lowest_altitude_through_decimation(Real decimation_floor, int* left) {
  constexpr Real kLMin = 0.05;
  RemeshMesh mesh(testing::jittered_two_label_box(21));
  make_constrained_delaunay(mesh);
  const Real start_floor = std::min(kLMin, min_altitude(mesh));
  RefinementSettings settings;
  settings.l_min = kLMin;
  settings.floor_altitudes = true;
  Decimator decimator;
  decimator.set_altitude_floor(decimation_floor);
  Real lowest = kInfinity;
  for (int round = 0; round < 6; ++round) {
    // A ball sliding along x: refined where it is, decimated where it was.
    const Vec3 centre(0.2 + 0.12 * round, 0.5, 0.6);
    refine(mesh, sphere_size_field(centre, 0.25, 0.08), settings);
    if (decimation_floor > 0) {  // else earlier fills may already be lower
      EXPECT_GE(min_altitude(mesh), start_floor) << "refinement broke its floor, round " << round;
    }
    const SizeField keep = sphere_size_field(centre, 0.3, 0.08);
    decimator.collect(mesh, keep);
    for (int call = 0; call < 50 && decimator.pending() > 0; ++call) {
      if (decimator.step(mesh, keep, 10).stuck) break;
      lowest = std::min(lowest, min_altitude(mesh));
    }
  }
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  *left = decimator.pending();
  return lowest;
}

// Decimation under the altitude floor never leaves a tet lower than the floor (so the stable step
// keeps its floor through coarsening too); without it, fills go below it on this mesh. A vertex
// whose fill would break the floor stays, to be retried once its neighbours have changed.
TEST(Decimation, AltitudeFloorHoldsThroughDecimation) {
  RemeshMesh start(testing::jittered_two_label_box(21));
  make_constrained_delaunay(start);
  const Real floor = std::min(0.05, min_altitude(start));
  int left_floored = 0, left_free = 0;
  EXPECT_GE(lowest_altitude_through_decimation(floor, &left_floored), floor);
  EXPECT_LT(lowest_altitude_through_decimation(0, &left_free), floor);
  EXPECT_EQ(left_free, 0);
  std::printf("altitude floor %.4f: %d vertices left by the floor, none without it\n", floor,
              left_floored);
}

TEST(Decimation, AltitudeFloorMustBeFiniteAndNonNegative) {
  Decimator decimator;
  EXPECT_THROW(decimator.set_altitude_floor(-1e-3), std::invalid_argument);
  EXPECT_THROW(decimator.set_altitude_floor(kInfinity), std::invalid_argument);
  decimator.set_altitude_floor(2e-3);
  EXPECT_EQ(decimator.altitude_floor(), 2e-3);
}

}  // namespace
}  // namespace incise::sim::remesh
