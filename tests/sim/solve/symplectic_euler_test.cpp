#include "sim/solve/symplectic_euler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sim/mesh/box_mesher.h"
#include "sim/models/mass_spring.h"

namespace incise::sim {
namespace {

const Prescribed kNothingPrescribed{};

TEST(SymplecticEuler, FreeFallFollowsTheDiscreteClosedForm) {
  // v_n = n dt g;  x_n = x_0 + dt^2 g n (n + 1) / 2 (velocity first, then position).
  Points x(1, 3);
  x << 0.5, -1, 2;
  const Points x0 = x;
  Points v = Points::Zero(1, 3);
  const Points f = Points::Zero(1, 3);
  const VecX inv_mass = VecX::Constant(1, 2.0);
  const Vec3 g(0, 0, -9.81);
  const Real dt = 1e-3;
  const int n = 250;
  for (int step = 0; step < n; ++step) {
    symplectic_euler_step(dt, g, inv_mass, kNothingPrescribed, f, x, v);
  }
  EXPECT_TRUE(row3(v, 0).isApprox(n * dt * g, 1e-12));
  const Vec3 expected = row3(x0, 0) + dt * dt * g * (n * (n + 1) / 2.0);
  EXPECT_TRUE(row3(x, 0).isApprox(expected, 1e-12));
}

TEST(SymplecticEuler, ForceAcceleratesByItsOverMass) {
  Points x = Points::Zero(1, 3);
  Points v = Points::Zero(1, 3);
  Points f(1, 3);
  f << 4, 0, -2;
  symplectic_euler_step(0.1, Vec3::Zero(), VecX::Constant(1, 0.5), kNothingPrescribed, f, x, v);
  EXPECT_TRUE(row3(v, 0).isApprox(Vec3(0.2, 0, -0.1), 1e-15));
  EXPECT_TRUE(row3(x, 0).isApprox(Vec3(0.02, 0, -0.01), 1e-15));
}

TEST(SymplecticEuler, ZeroInverseMassNodeIgnoresForcesAndGravity) {
  Points x(2, 3);
  x << 0, 0, 0, 1, 1, 1;
  const Points x0 = x;
  Points v = Points::Zero(2, 3);
  const Points f = Points::Constant(2, 3, 5.0);
  VecX inv_mass(2);
  inv_mass << 0, 1;
  for (int step = 0; step < 10; ++step) {
    symplectic_euler_step(1e-2, Vec3(0, 0, -9.81), inv_mass, kNothingPrescribed, f, x, v);
  }
  EXPECT_EQ(row3(x, 0), row3(x0, 0));
  EXPECT_EQ(row3(v, 0), Vec3::Zero());
  EXPECT_NE(row3(x, 1), row3(x0, 1));
}

TEST(SymplecticEuler, PrescribedAxesAreHeldOthersMove) {
  Points x(1, 3);
  x << 1, 2, 3;
  Points v = Points::Zero(1, 3);
  const Points f = Points::Constant(1, 3, 1.0);
  Prescribed prescribed;
  prescribed.mask.resize(1, 3);
  prescribed.mask << 1, 0, 0;  // x held at 1, like "fix": "x"
  prescribed.position = x;
  for (int step = 0; step < 20; ++step) {
    symplectic_euler_step(1e-2, Vec3(-9.81, 0, -9.81), VecX::Ones(1), prescribed, f, x, v);
  }
  EXPECT_EQ(x(0, 0), 1);
  EXPECT_EQ(v(0, 0), 0);
  EXPECT_GT(x(0, 1), 2);  // pushed by f
  EXPECT_LT(x(0, 2), 3);  // gravity wins over f
}

TEST(SymplecticEuler, PrescribedPositionIsReachedWithTheMatchingVelocity) {
  Points x(1, 3);
  x << 0, 0, 0;
  Points v = Points::Zero(1, 3);
  Prescribed prescribed;
  prescribed.mask = AxisMask::Ones(1, 3);
  prescribed.position.resize(1, 3);
  prescribed.position << 0.01, -0.02, 0.03;
  symplectic_euler_step(0.5, Vec3(0, 0, -9.81), VecX::Ones(1), prescribed, Points::Zero(1, 3), x,
                        v);
  EXPECT_EQ(row3(x, 0), row3(prescribed.position, 0));
  EXPECT_TRUE(row3(v, 0).isApprox(Vec3(0.02, -0.04, 0.06), 1e-15));
}

// Symplectic Euler keeps an undamped oscillator's energy within O(omega dt) of its start for any
// number of steps; explicit Euler would multiply it by (1 + (omega dt)^2) every step, i.e. by
// e^100 over this run.
TEST(SymplecticEuler, OscillatorEnergyStaysBoundedOverManySteps) {
  const Real k = 100;
  const Real m = 1;
  const Real omega = std::sqrt(k / m);
  const Real dt = 0.01;  // omega dt = 0.1
  Points x(1, 3);
  x << 1, 0, 0;
  Points v = Points::Zero(1, 3);
  Points f(1, 3);
  const auto energy = [&] { return 0.5 * m * v.squaredNorm() + 0.5 * k * x.squaredNorm(); };
  const Real e0 = energy();
  Real worst = 0;
  for (int step = 0; step < 100000; ++step) {
    f = -k * x;
    symplectic_euler_step(dt, Vec3::Zero(), VecX::Constant(1, 1 / m), kNothingPrescribed, f, x, v);
    worst = std::max(worst, std::abs(energy() - e0) / e0);
  }
  EXPECT_LT(worst, omega * dt);
}

TEST(SymplecticEuler, FreeBodyAtRestStaysExactlyAtRest) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.05), Vec3i(3, 2, 4));
  const MassSpring model(mesh.rest, mesh.tets, {3000, 1000, 0.3});
  const VecX inv_mass = model.masses().cwiseInverse();
  Points x = mesh.rest;
  Points v = Points::Zero(mesh.num_nodes(), 3);
  Points f(mesh.num_nodes(), 3);
  for (int step = 0; step < 2000; ++step) {
    f.setZero();
    model.add_forces(x, v, f);
    symplectic_euler_step(1e-4, Vec3::Zero(), inv_mass, kNothingPrescribed, f, x, v);
  }
  EXPECT_TRUE((v.array() == 0).all());  // bitwise, not approximately
  EXPECT_TRUE((x.array() == mesh.rest.array()).all());
}

}  // namespace
}  // namespace incise::sim
