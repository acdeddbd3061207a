// Hard cases released from a state run_scene_on cannot start from (it starts at rest): a node
// yanked five body lengths away, and a tet pushed through its opposite face. The scene's model
// (make_model, so the same materials and damping as a scene run) is stepped by implicit Euler with
// the base clamped; after release the body must come back to its rest shape within 1% of its
// size, or, for a model that cannot cope, say so through health().inverted_elements. The scene
// names implicit_euler, so St Venant-Kirchhoff and Neo-Hookean get the projected (positive
// semi-definite) tangent as in a scene run (scene_run.h, projected_tangent.h).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "sim/mesh/box_mesher.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/implicit_euler.h"

namespace incise::sim {
namespace {

constexpr Real kSize = 0.02;  // cube edge [m]
constexpr Real kE = 3000, kNu = 0.3, kDensity = 1000;

std::string name_of(MaterialModel model) {
  switch (model) {
    case MaterialModel::mass_spring:
      return "mss";
    case MaterialModel::linear:
      return "linear";
    case MaterialModel::corotational:
      return "corotational";
    case MaterialModel::corotational_polar:
      return "corotational_polar";
    case MaterialModel::corotational_nodal_pressure:
      return "corotational_nodal_pressure";
    case MaterialModel::stvk:
      return "stvk";
    case MaterialModel::neohookean:
      return "neohookean";
  }
  return "?";
}

// A body under implicit Euler as run_scene_on sets it up (CG to 1e-8, as many iterations as it
// may need), its base z = 0 clamped, starting from x with v = 0.
class ClampedCube {
 public:
  ClampedCube(MaterialModel model, Real damping, const TetMesh& mesh, Points x)
      : mesh_(mesh),
        x_(std::move(x)),
        v_(Points::Zero(mesh.num_nodes(), 3)),
        integrator_(implicit_settings(mesh)) {
    Scene scene;
    scene.material = {model, kE, kNu, kDensity, damping};
    scene.solver.integrator = Integrator::implicit_euler;
    model_ = make_model(scene, mesh);
    prescribed_.mask = AxisMask::Zero(mesh.num_nodes(), 3);
    prescribed_.position = mesh.rest;
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      if (mesh.rest(i, 2) == 0) prescribed_.mask.row(i).setOnes();
    }
  }

  // Holds node on all axes at position (until release).
  void hold(int node, const Vec3& position) {
    prescribed_.mask.row(node).setOnes();
    prescribed_.position.row(node) = position.transpose();
  }
  void release(int node) { prescribed_.mask.row(node).setZero(); }

  // steps steps of dt; false as soon as one is not finite.
  bool step(Real dt, int steps) {
    for (int n = 0; n < steps; ++n) {
      const auto report =
          integrator_.step(dt, Vec3::Zero(), Points(), prescribed_, *model_, x_, v_);
      if (!report.finite) return false;
      unconverged_steps_ += report.converged ? 0 : 1;
    }
    return true;
  }

  // The largest node distance from rest over the cube's edge.
  Real shape_error() const { return (x_ - mesh_.rest).rowwise().norm().maxCoeff() / kSize; }
  // Inverted tets at the current state (evaluates the forces, which updates health()).
  int inverted_elements() {
    Points f = Points::Zero(mesh_.num_nodes(), 3);
    model_->add_forces(x_, v_, f);
    return model_->health().inverted_elements;
  }
  // Inverted tets counted from the positions alone, to check what the model says.
  int counted_inverted_elements() const {
    return (tet_volumes(x_, mesh_.tets).array() <= 0).count();
  }
  const Points& x() const { return x_; }
  int unconverged_steps() const { return unconverged_steps_; }

 private:
  static ImplicitEulerSettings implicit_settings(const TetMesh& mesh) {
    ImplicitEulerSettings settings;
    settings.linear.cg.tolerance = 1e-8;
    settings.linear.cg.max_iterations = 10 * mesh.num_nodes() + 100;
    return settings;
  }

  const TetMesh& mesh_;
  Points x_, v_;
  std::unique_ptr<Model> model_;
  ImplicitEuler integrator_;
  Prescribed prescribed_;
  int unconverged_steps_ = 0;
};

// Whether the model promises to undo inversion (its header): St Venant-Kirchhoff has mirrored
// rest states, and the scene's mass-spring model is built without its volume term, so springs
// alone cannot tell a tet from its mirror image.
bool restores_inversion(MaterialModel model) {
  return model != MaterialModel::stvk && model != MaterialModel::mass_spring;
}

// The top corner node (4, 4, 4) of the 4 x 4 x 4 cube is dragged 5 cube edges away along the
// diagonal in 20 steps, then let go. Steps of 5 ms are about 7 times the explicit limit.
struct YankOutcome {
  bool finite = false;
  Real held_distance = 0;           // [cube edges] when released
  Real shape_error = 0;             // after the release steps
  int inverted_at_end = 0;          // as the model reports it (health())
  int counted_inverted_at_end = 0;  // det F <= 0 counted from the positions
  int unconverged_steps = 0;
};

YankOutcome yank_and_release(MaterialModel model, Real damping, Real dt, int release_steps) {
  static const TetMesh mesh = make_box_mesh(Vec3(kSize, kSize, kSize), Vec3i(4, 4, 4));
  const int node = 4 + 5 * (4 + 5 * 4);
  const Vec3 rest = row3(mesh.rest, node);
  const Vec3 far = rest + 5 * kSize * Vec3(1, 1, 1).normalized();
  ClampedCube cube(model, damping, mesh, mesh.rest);
  YankOutcome out;
  constexpr int kDragSteps = 20;
  for (int n = 0; n < kDragSteps; ++n) {
    cube.hold(node, rest + Real(n + 1) / kDragSteps * (far - rest));
    if (!cube.step(dt, 1)) return out;
  }
  out.held_distance = (row3(cube.x(), node) - rest).norm() / kSize;
  cube.release(node);
  out.finite = cube.step(dt, release_steps);
  out.shape_error = cube.shape_error();
  out.inverted_at_end = cube.inverted_elements();
  out.counted_inverted_at_end = cube.counted_inverted_elements();
  out.unconverged_steps = cube.unconverged_steps();
  return out;
}

TEST(HardCaseRelease, NodeYankedFiveBodyLengthsAwayComesBackToRest) {
  for (const auto model :
       {MaterialModel::mass_spring, MaterialModel::linear, MaterialModel::corotational,
        MaterialModel::corotational_polar, MaterialModel::stvk, MaterialModel::neohookean}) {
    SCOPED_TRACE(name_of(model));
    const YankOutcome out = yank_and_release(model, 0.1, 5e-3, 400);
    ASSERT_TRUE(out.finite);
    EXPECT_NEAR(out.held_distance, 5, 1e-12);
    if (model == MaterialModel::mass_spring) {
      // It cannot untangle the tets the snap-back turned inside out (no volume term), and says
      // so: measured 112 inverted tets, 2.5 cube edges from rest.
      EXPECT_TRUE(out.shape_error < 0.01 || out.inverted_at_end > 0) << out.shape_error;
      continue;
    }
    EXPECT_LT(out.shape_error, 0.01);  // measured 1e-9 to 4e-9
    EXPECT_EQ(out.inverted_at_end, 0);
  }
}

// The Neo-Hookean model at 2 ms steps (about 3 times the explicit limit; 5 ms passes above). The
// snap-back inverts tets, where the model's exact Hessian is indefinite (it already is under
// moderate compression, neo_hookean_fem.h); implicit Euler takes one linearisation per step and CG
// stops at the negative curvature. With the exact Hessian as K this run blew up (measured 8.3e15
// cube edges from rest, 174 inverted tets, 991 of 1000 CG solves unconverged, every step
// "finite"). With the projected tangent every CG solve converges and the body comes back: measured
// 2.2e-4 of the edge, no inverted tet.
TEST(HardCaseRelease, NeoHookeanYankReleasedAtThreeTimesTheExplicitLimit) {
  const YankOutcome out = yank_and_release(MaterialModel::neohookean, 0.1, 2e-3, 1000);
  ASSERT_TRUE(out.finite);
  EXPECT_NEAR(out.held_distance, 5, 1e-12);
  EXPECT_LT(out.shape_error, 0.01);
  EXPECT_EQ(out.inverted_at_end, 0);
  EXPECT_EQ(out.unconverged_steps, 0);
}

// Corotational (QR) with damping 1 (critical for the mesh's highest mode) at 2 ms. It used to stay
// tangled (62.8 cube edges from rest with 214 inverted tets after 500 steps; the tangle was
// chaotic): QR's frame puts every inversion on its third column (rotation_extraction.h), and the
// restoring force can turn a tet into a 180-degree rotated copy of its rest shape instead of
// undoing the inversion. Since the viscous stress is capped for stretched tets
// (tet_fem_model.h: beta min(1, 3 / |F|^2)) it recovers in this run (measured shape error 1.3e-3,
// no inverted tet); the frame's weakness is still there, so the polar rotation stays the scenes'
// choice. The metric is true either way.
TEST(HardCaseRelease, CorotationalQrYankReleasedWithFullDampingRecoversAndSaysSo) {
  const YankOutcome qr = yank_and_release(MaterialModel::corotational, 1.0, 2e-3, 500);
  ASSERT_TRUE(qr.finite);
  EXPECT_LT(qr.shape_error, 0.01);
  EXPECT_EQ(qr.inverted_at_end, 0);
  // The metric is true: the model's count is the count of det F <= 0 from the positions.
  EXPECT_EQ(qr.inverted_at_end, qr.counted_inverted_at_end);

  const YankOutcome polar = yank_and_release(MaterialModel::corotational_polar, 1.0, 2e-3, 500);
  ASSERT_TRUE(polar.finite);
  EXPECT_LT(polar.shape_error, 0.01);
  EXPECT_EQ(polar.inverted_at_end, 0);
}

// The 3 x 3 x 3 cube's top corner (3, 3, 3) belongs to one tet only (the corner tet of its cell,
// box_mesher.h); mirroring it through the plane of its three neighbours pushes that tet through
// its opposite face and leaves every other tet as it was.
struct InvertedStart {
  TetMesh mesh = make_box_mesh(Vec3(kSize, kSize, kSize), Vec3i(3, 3, 3));
  Points x;
  InvertedStart() {
    x = mesh.rest;
    const int corner = 3 + 4 * (3 + 4 * 3);
    const Real cell = kSize / 3;
    x.row(corner) -= Eigen::RowVector3d(1, 1, 1) * (2 * cell / 3);  // twice its altitude a / sqrt 3
  }
};

struct InversionOutcome {
  bool finite = false;
  int inverted_at_start = 0;
  int inverted_at_end = 0;
  Real shape_error = 0;
  int unconverged_steps = 0;  // steps whose CG solve missed its tolerance
};

InversionOutcome release_inverted(MaterialModel model, Real dt, int steps) {
  static const InvertedStart start;
  ClampedCube cube(model, 0.1, start.mesh, start.x);
  InversionOutcome out;
  out.inverted_at_start = cube.inverted_elements();
  out.finite = cube.step(dt, steps);
  out.inverted_at_end = cube.inverted_elements();
  out.shape_error = cube.shape_error();
  out.unconverged_steps = cube.unconverged_steps();
  return out;
}

TEST(HardCaseRelease, TetPushedThroughItsOppositeFaceTurnsBack) {
  // 1 ms is about the explicit limit of this mesh (0.96 ms); 1 s of simulated time.
  for (const auto model :
       {MaterialModel::mass_spring, MaterialModel::linear, MaterialModel::corotational,
        MaterialModel::corotational_polar, MaterialModel::stvk, MaterialModel::neohookean}) {
    SCOPED_TRACE(name_of(model));
    const InversionOutcome out = release_inverted(model, 1e-3, 1000);
    ASSERT_TRUE(out.finite);
    EXPECT_EQ(out.inverted_at_start, 1);
    if (restores_inversion(model)) {
      // Measured 6e-5 (linear), 3.8e-4 (QR), 4.0e-4 (polar), 5.8e-6 (Neo-Hookean; 1.2e-3 with its
      // exact Hessian as K, whose CG stopped at negative curvature in 2 of the steps).
      EXPECT_LT(out.shape_error, 0.01);
      EXPECT_EQ(out.inverted_at_end, 0);
      // Linear and corotational K are positive semi-definite in every state, and the Neo-Hookean
      // K of a time step is the projected one, so every CG solve must converge.
      EXPECT_EQ(out.unconverged_steps, 0);
    } else {
      // A mirrored tet is a rest state of these two: no force turns it back, and they say so.
      EXPECT_EQ(out.inverted_at_end, 1);
    }
  }
}

// The same at 3 ms (3 times the explicit limit). With the exact Hessian as K (indefinite while the
// tet is inverted) CG could stop at negative curvature; this once diverged (to 8.8e39 cube edges)
// when ImplicitEuler kept the warm-start guess of such a broken-down solve. With the projected
// tangent every solve converges: measured 3.3e-11 of the edge.
TEST(HardCaseRelease, NeoHookeanTetPushedThroughItsFaceAtThreeTimesTheLimit) {
  const InversionOutcome out = release_inverted(MaterialModel::neohookean, 3e-3, 1000);
  ASSERT_TRUE(out.finite);
  EXPECT_LT(out.shape_error, 0.01);
  EXPECT_EQ(out.inverted_at_end, 0);
  EXPECT_EQ(out.unconverged_steps, 0);
}

}  // namespace
}  // namespace incise::sim
