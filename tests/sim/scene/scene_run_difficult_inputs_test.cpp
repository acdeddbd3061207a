// Hard cases run as scenes (run_scene_on): nu = 0.499, a mesh with a layer of slivers, implicit
// steps at ten times the explicit limit, and a million explicit steps at rest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include "sim/mesh/box_mesher.h"
#include "sim/mesh/mesh_quality.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/stable_time_step.h"

#include "tests/sim/closed_forms.h"

namespace incise::sim {
namespace {

constexpr Real kSize = 0.02;  // [m]
constexpr Real kE = 3000;     // soft tissue [Pa]
constexpr Real kDensity = 1000;
constexpr Real kEps = 1e-9;                       // selection half-width [m]
constexpr Real kDegree = std::numbers::pi / 180;  // [rad]

const MaterialModel kFemModels[] = {MaterialModel::linear, MaterialModel::corotational,
                                    MaterialModel::corotational_polar, MaterialModel::stvk,
                                    MaterialModel::neohookean};

Scene scene_of(MaterialModel model, Real poisson_ratio, Integrator integrator) {
  Scene scene;
  // The tests hand run_scene_on their own meshes; the spec only has to be valid.
  scene.mesh.source = MeshSource::file;
  scene.mesh.file = "(built by the test)";
  scene.material = {model, kE, poisson_ratio, kDensity, 0.0};
  scene.solver = {integrator, 1.0, 1, 1e-10};
  return scene;
}

Constraint clamp_below(Real z) {
  return {{Box3(Vec3(-1, -1, -1), Vec3(1, 1, z + kEps))}, {true, true, true}, Vec3::Zero()};
}

// --- nu = 0.499 ----------------------------------------------------------------------------------

TEST(HardCaseScene, NearlyIncompressibleNeoHookeanCompressionMatchesJoshiEq15) {
  constexpr Real kNu = 0.499;
  const TetMesh mesh = make_box_mesh(Vec3(kSize, kSize, kSize), Vec3i(3, 3, 3));
  for (const Real strain : {0.05, 0.10, 0.20}) {
    SCOPED_TRACE(strain);
    Scene scene = scene_of(MaterialModel::neohookean, kNu, Integrator::static_equilibrium);
    scene.solver.steps = 4;  // load increments
    // Symmetry planes x = 0 and y = 0, base z = 0 held in z; the top moves down by strain.
    scene.constraints = {
        {{Box3(Vec3(-kEps, -1, -1), Vec3(kEps, 1, 1))}, {true, false, false}, Vec3::Zero()},
        {{Box3(Vec3(-1, -kEps, -1), Vec3(1, kEps, 1))}, {false, true, false}, Vec3::Zero()},
        {{Box3(Vec3(-1, -1, -kEps), Vec3(1, 1, kEps))}, {false, false, true}, Vec3::Zero()},
        {{Box3(Vec3(-1, -1, kSize - kEps), Vec3(1, 1, kSize + kEps))},
         {false, false, true},
         Vec3(0, 0, -strain * kSize)},
    };
    const auto result = run_scene_on(scene, mesh);
    ASSERT_TRUE(result.finite);
    ASSERT_TRUE(result.converged) << result.relative_residual;
    const auto lame = test::lame_parameters(kE, kNu);
    const Real l2 = test::neo_hookean_lateral_stretch(1 - strain, lame.mu, lame.lambda);
    // Nearly incompressible: the volume ratio l1 l2^2 stays within 0.2% of 1 up to 20%
    // (measured 0.99990, 0.99978, 0.99950 at 5, 10, 20%).
    EXPECT_NEAR((1 - strain) * l2 * l2, 1, 2e-3);
    Real worst = 0, scale = 0;
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      const Vec3 p = row3(mesh.rest, i);
      const Vec3 expected((l2 - 1) * p.x(), (l2 - 1) * p.y(), -strain * p.z());
      worst = std::max(worst, (row3(result.displacement, i) - expected).norm());
      scale = std::max(scale, expected.norm());
    }
    // A homogeneous stretch is exact on linear tets: what is left is the solver's tolerance
    // (measured 7e-15, 3e-15, 7e-13).
    EXPECT_LT(worst / scale, 1e-6);
  }
}

// --- Slivers and large steps --------------------------------------------------------------------

// A body clamped at its base, released at rest under gravity and run by implicit Euler for
// `duration` at step dt, set against the static answer of the same scene.
struct Settling {
  bool finite = false;
  bool converged = false;  // every CG solve met its tolerance
  Real max_speed = 0;      // [m/s] at the end
  Real static_error = 0;   // largest node distance from the static answer / the static sag
};

Settling settle_under_gravity(MaterialModel model, const TetMesh& mesh, Real dt, Real duration) {
  Scene scene = scene_of(model, 0.3, Integrator::implicit_euler);
  scene.material.damping = 0.05;
  scene.gravity = Vec3(0, 0, -9.81);
  scene.constraints = {clamp_below(0)};
  scene.solver.dt = dt;
  scene.solver.steps = static_cast<std::int64_t>(std::ceil(duration / dt));
  scene.solver.tolerance = 1e-8;
  const auto dynamic = run_scene_on(scene, mesh);
  Settling out;
  out.finite = dynamic.finite;
  out.converged = dynamic.converged;
  out.max_speed = dynamic.max_speed;
  scene.solver = {Integrator::static_equilibrium, 1.0, 1, 1e-10};
  const auto statics = run_scene_on(scene, mesh);
  EXPECT_TRUE(statics.converged);
  const Real sag = statics.displacement.rowwise().norm().maxCoeff();
  EXPECT_GT(sag, 0);
  out.static_error =
      (dynamic.displacement - statics.displacement).rowwise().norm().maxCoeff() / sag;
  return out;
}

// A 4 x 4 x 4 cube whose middle layer of cells (between grid planes k = 2 and 3) is squeezed to
// 2% of the others' height. Each tet lies in one cell, which the squeeze maps affinely with a
// positive determinant, so every tet stays positive; in the thin layer the central tets become
// slivers (two opposite edges in planes 0.1 mm apart, crossing when seen from above: four nearly
// coplanar nodes, no short edge) and the corner tets flat wedges.
TetMesh cube_with_a_sliver_layer() {
  const Real cell = kSize / 4;
  TetMesh box = make_box_mesh(Vec3(kSize, kSize, kSize), Vec3i(4, 4, 4));
  const Real level[] = {0, cell, 2 * cell, 2.02 * cell, 3.02 * cell};
  Points rest = box.rest;
  for (int i = 0; i < rest.rows(); ++i) {
    rest(i, 2) = level[static_cast<int>(std::lround(box.rest(i, 2) / cell))];
  }
  return make_tet_mesh(rest, box.tets);
}

TEST(HardCaseScene, SliverLayerUnderGravitySettlesOnTheStaticAnswer) {
  const TetMesh mesh = cube_with_a_sliver_layer();
  const QualitySummary quality = summarize_quality(mesh.rest, mesh.tets);
  ASSERT_EQ(quality.num_inverted, 0);
  ASSERT_EQ(quality.num_degenerate, 0);
  int slivers = 0;
  for (const TetQuality& q : mesh_quality(mesh.rest, mesh.tets)) {
    if (q.min_dihedral < 3 * kDegree && q.max_dihedral > 170 * kDegree) ++slivers;
  }
  EXPECT_EQ(slivers, 16);  // one per cell of the layer
  // 2 ms steps: 80 times the explicit limit the slivers set (2.8 times the unsqueezed cube's).
  const Real dt = 2e-3;
  EXPECT_GT(dt / stable_time_step(mesh, kE, 0.3, kDensity), 50);
  for (const MaterialModel model : kFemModels) {
    SCOPED_TRACE(static_cast<int>(model));
    // Measured: speeds below 2e-15 m/s, 1e-14 to 1.5e-11 of the sag from the static answer.
    const Settling out = settle_under_gravity(model, mesh, dt, 1.0);
    ASSERT_TRUE(out.finite);
    EXPECT_TRUE(out.converged);
    EXPECT_LT(out.max_speed, 1e-4);
    EXPECT_LT(out.static_error, 1e-2);
  }
}

TEST(HardCaseScene, ImplicitEulerAtTenTimesTheExplicitLimitSettlesForEveryFemModel) {
  const TetMesh mesh = make_box_mesh(Vec3(kSize, kSize, kSize), Vec3i(3, 3, 3));
  const Real dt = 10 * stable_time_step(mesh, kE, 0.3, kDensity);  // 9.6 ms
  for (const MaterialModel model : kFemModels) {
    SCOPED_TRACE(static_cast<int>(model));
    // Measured: speeds below 5e-16 m/s, 6e-15 to 1.4e-11 of the sag from the static answer.
    const Settling out = settle_under_gravity(model, mesh, dt, 3.0);
    ASSERT_TRUE(out.finite);
    EXPECT_TRUE(out.converged);
    EXPECT_LT(out.max_speed, 1e-4);
    EXPECT_LT(out.static_error, 1e-2);
  }
}

// --- A million steps at rest ---------------------------------------------------------------------

// One tet of no particular shape or position (no coordinate is a round number, so F = Ds Dm^-1
// at rest is the identity only up to round-off), free in space, undamped, no load.
TetMesh lone_tet() {
  Points rest(4, 3);
  rest << 0, 0, 0, 0.02, 0.001, 0.003, 0.004, 0.018, 0.002, 0.003, 0.005, 0.021;
  rest.rowwise() += Eigen::RowVector3d(0.1234, -0.0567, 0.0891);
  Tets tets(1, 4);
  tets << 0, 1, 2, 3;
  return make_tet_mesh(rest, tets);
}

TEST(HardCaseScene, AMillionExplicitStepsAtRestStayAtRest) {
  const TetMesh mesh = lone_tet();
  ASSERT_GT(tet_volumes(mesh.rest, mesh.tets)(0), 0);
  for (const MaterialModel model :
       {MaterialModel::mass_spring, MaterialModel::linear, MaterialModel::corotational,
        MaterialModel::corotational_polar, MaterialModel::stvk, MaterialModel::neohookean}) {
    for (const Integrator integrator :
         {Integrator::symplectic_euler, Integrator::central_difference}) {
      SCOPED_TRACE(std::to_string(static_cast<int>(model)) + " " +
                   std::to_string(static_cast<int>(integrator)));
      Scene scene = scene_of(model, 0.3, integrator);
      scene.solver.dt = stable_time_step(mesh, kE, 0.3, kDensity);
      scene.solver.steps = 1'000'000;
      const auto result = run_scene_on(scene, mesh);
      ASSERT_TRUE(result.finite);
      EXPECT_EQ(result.steps, 1'000'000);
      // Measured: exactly 0 for the mass-spring model (its rest lengths are the rest
      // distances); up to 1.3e-14 m (6e-13 of the tet's size) for the FEM models, growing like the
      // square root of the step count (2e-15 m after 1e5 steps, 2e-14 m after 4e6): a random
      // walk of round-off around rest, no systematic drift.
      const Real drift = result.displacement.cwiseAbs().maxCoeff();
      EXPECT_LE(drift, 1e-12 * kSize) << drift;
      EXPECT_LE(result.max_speed, 1e-12 * kSize / scene.solver.dt) << result.max_speed;
    }
  }
}

}  // namespace
}  // namespace incise::sim
