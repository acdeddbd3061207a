// State transfer by barycentric interpolation in the rest host tet, and the l_min / dt_min floor.

#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "remesh_fixtures.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/refinement.h"
#include "sim/remesh/remesh_validity.h"
#include "sim/remesh/state_transfer.h"
#include "sim/remesh/time_step_floor.h"
#include "sim/solve/stable_time_step.h"

namespace incise::sim::remesh {
namespace {

TEST(StateTransfer, BarycentricReproducesThePoint) {
  const std::array<Vec3, 4> tet = {Vec3(0.1, 0.2, 0.3), Vec3(1.3, 0.1, 0.2), Vec3(0.2, 1.1, 0.4),
                                   Vec3(0.3, 0.2, 0.9)};
  const Vec3 p(0.4, 0.35, 0.41);
  const Weights4 w = barycentric(tet, p);
  EXPECT_NEAR(w.sum(), 1, 1e-15);
  EXPECT_LT((interpolate(tet, w) - p).norm(), 1e-15);
  EXPECT_GT(w.minCoeff(), 0);  // p is inside
  // At a corner, the weights are that corner's unit vector.
  const Weights4 corner = barycentric(tet, tet[2]);
  EXPECT_NEAR(corner[2], 1, 1e-15);
  EXPECT_NEAR(corner[0] + corner[1] + corner[3], 0, 1e-15);
  const std::array<Vec3, 4> flat = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  EXPECT_THROW(barycentric(flat, p), std::invalid_argument);
}

// A whole refinement with the listener wired as a model would be: each new vertex gets its
// deformed position and velocity interpolated from its host tet's nodes. Under an affine
// deformation x = A X + b and an affine velocity field, every vertex then carries the exact
// field value at its rest point (up to rounding), whether inserted in a tet, on a face, on an
// edge or on a constrained surface.
TEST(StateTransfer, AffineFieldsAreReproducedAtEveryNewVertex) {
  RemeshMesh mesh(testing::jittered_two_label_box(13));
  make_constrained_delaunay(mesh);
  Mat3 a, velocity_gradient;
  a << 1.2, 0.1, -0.3, 0.05, 0.9, 0.2, -0.1, 0.3, 1.1;
  velocity_gradient << 0.0, -2.0, 0.5, 2.0, 0.1, 0.0, -0.5, 0.0, 0.3;
  const Vec3 b(0.3, -0.2, 0.7), v0(0.01, 0.02, -0.03);
  const auto x_of = [&](const Vec3& rest) -> Vec3 { return a * rest + b; };
  const auto v_of = [&](const Vec3& rest) -> Vec3 { return velocity_gradient * rest + v0; };
  // Deformed state by vertex slot, as a model would hold it.
  std::vector<Vec3> x(static_cast<size_t>(mesh.num_vertex_slots())), v(x.size());
  for (int i = 0; i < mesh.num_vertex_slots(); ++i) {
    x[static_cast<size_t>(i)] = x_of(mesh.point(i));
    v[static_cast<size_t>(i)] = v_of(mesh.point(i));
  }
  int transfers = 0;
  RemeshListener listener;
  listener.on_inserted = [&](const InsertedVertex& n, const TetChanges& changes) {
    ASSERT_FALSE(changes.created.empty());
    std::array<Vec3, 4> host_x, host_v, host_rest;
    for (int k = 0; k < 4; ++k) {
      const auto h = static_cast<size_t>(n.host[k]);
      host_x[k] = x[h];
      host_v[k] = v[h];
      host_rest[k] = mesh.point(n.host[k]);
    }
    EXPECT_NEAR(n.weights.sum(), 1, 1e-14);
    EXPECT_LT((interpolate(host_rest, n.weights) - n.rest_point).norm(), 1e-14);
    EXPECT_GE(n.weights.minCoeff(), -1e-12);  // the host tet holds the point
    const auto i = static_cast<size_t>(n.vertex);
    if (i >= x.size()) x.resize(i + 1), v.resize(i + 1);
    x[i] = interpolate(host_x, n.weights);
    v[i] = interpolate(host_v, n.weights);
    ++transfers;
  };
  RefinementSettings settings;
  settings.l_min = 0.03;
  const RefinementStats stats =
      refine(mesh, sphere_size_field(Vec3(0.5, 0.5, 0.5), 0.4, 0.09), settings, listener);
  ASSERT_GT(stats.insertions(), 50);
  EXPECT_GT(stats.constraint_splits + stats.on_face + stats.on_edge, 0);
  EXPECT_EQ(transfers, stats.insertions() + stats.rolled_back);
  EXPECT_EQ(check_remesh_mesh(mesh), "");
  for (int i = mesh.num_original_vertices(); i < mesh.num_vertex_slots(); ++i) {
    if (!mesh.vertex_alive(i)) continue;
    const auto s = static_cast<size_t>(i);
    EXPECT_LT((x[s] - x_of(mesh.point(i))).norm(), 1e-14) << "vertex " << i;
    EXPECT_LT((v[s] - v_of(mesh.point(i))).norm(), 1e-14) << "vertex " << i;
  }
}

// l_min <-> dt_min round trip, and agreement with sim/solve's floor for a material.
TEST(TimeStepFloor, RoundTripAndAgreesWithStableTimeStep) {
  const Real e = 4000, nu = 0.475, rho = 1050;  // the seed's liver
  const Real c = p_wave_speed(e, nu, rho);
  for (Real l : {1e-4, 2.5e-3, 0.01}) {
    const Real dt = dt_min_for_l_min(l, c);
    EXPECT_NEAR(l_min_for_dt_min(dt, c), l, 1e-15 * l);
    EXPECT_NEAR(dt, time_step_floor(l, e, nu, rho), 1e-15 * dt);
    EXPECT_NEAR(l_min_for_dt_min(dt, c, 0.8), length_floor(dt, e, nu, rho, 0.8), 1e-15 * l);
  }
  // The seed's scaling: l_min dt_min / dt_c for the length that keeps a mesh above dt_min.
  EXPECT_NEAR(l_min_for_dt_min(5e-4, c) / l_min_for_dt_min(1e-3, c), 0.5, 1e-15);
  EXPECT_THROW(dt_min_for_l_min(0, c), std::invalid_argument);
  EXPECT_THROW(l_min_for_dt_min(1e-3, 0), std::invalid_argument);
  EXPECT_THROW(l_min_for_dt_min(1e-3, c, 1.5), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::remesh
