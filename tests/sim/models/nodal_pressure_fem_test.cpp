// Averaged nodal pressure (nodal_pressure_fem.h): what sets it apart from the plain corotational
// tet. The laws every model obeys (net force and torque, rigid invariance, clones, local updates,
// hard cases) run over it through all_models().
#include <gtest/gtest.h>

#include <Eigen/Sparse>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "model_fixtures.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"
#include "sim/models/corotational_fem.h"
#include "sim/models/nodal_pressure_fem.h"
#include "sim/solve/static_solver.h"

namespace incise::sim::testing {
namespace {

// Under a uniform deformation every element has the same volume change, so the nodal averages
// equal it and the model is the plain corotational one.
TEST(NodalPressureFem, UniformDeformationGivesThePlainCorotationalForces) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  const auto materials = test_materials(0.45);
  for (unsigned seed : {1u, 2u, 3u}) {
    const Mat3 f = random_rotation(seed) * (Mat3::Identity() + Mat3(random_points(3, 0.15, seed)));
    const Points x = (mesh.rest * f.transpose()).eval();
    const Points v = Points::Zero(mesh.num_nodes(), 3);
    NodalPressureFem nodal(mesh, materials);
    CorotationalFem plain(mesh, materials, RotationExtraction::polar);
    const Points a = forces(nodal, x, v);
    const Points b = forces(plain, x, v);
    EXPECT_LT((a - b).norm(), 1e-9 * b.norm()) << "seed " << seed;
  }
}

// The forces are the exact gradient of potential_energy (central differences).
TEST(NodalPressureFem, ForcesAreMinusTheEnergyGradient) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  NodalPressureFem model(mesh, test_materials(0.45));
  const Points x = (mesh.rest + random_points(mesh.num_nodes(), 0.002, 7)).eval();
  const Points f = forces(model, x, Points::Zero(mesh.num_nodes(), 3));
  const Real h = 1e-7;
  Real worst = 0;
  for (int n = 0; n < mesh.num_nodes(); n += 3) {
    for (int c = 0; c < 3; ++c) {
      Points plus = x, minus = x;
      plus(n, c) += h;
      minus(n, c) -= h;
      const Real gradient =
          (model.potential_energy(plus) - model.potential_energy(minus)) / (2 * h);
      worst = std::max(worst, std::abs(gradient + f(n, c)));
    }
  }
  EXPECT_LT(worst, 1e-5 * f.cwiseAbs().maxCoeff());
}

// K dx through the element loops equals the assembled triplets, and at rest (where the
// corotational K is exact) it is the derivative of the forces.
TEST(NodalPressureFem, StiffnessActionMatchesTripletsAndForceDerivative) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  NodalPressureFem model(mesh, test_materials(0.45));
  const Points dx = random_points(mesh.num_nodes(), 1e-3, 11);
  const Points zero = Points::Zero(mesh.num_nodes(), 3);
  for (const bool deformed : {false, true}) {
    const Points x =
        deformed ? (mesh.rest + random_points(mesh.num_nodes(), 0.003, 5)).eval() : mesh.rest;
    model.prepare_stiffness(x);
    Points action = zero;
    model.add_stiffness_times(dx, action);
    std::vector<Eigen::Triplet<Real>> triplets;
    model.add_stiffness_triplets(triplets);
    Eigen::SparseMatrix<Real> k(3 * mesh.num_nodes(), 3 * mesh.num_nodes());
    k.setFromTriplets(triplets.begin(), triplets.end());
    const VecX assembled = k * flat(dx);
    EXPECT_LT((assembled - flat(action)).norm(), 1e-9 * assembled.norm()) << deformed;
    if (deformed) continue;
    const Real h = 1e-4;
    const Points fp = forces(model, (x + h * dx).eval(), zero);
    const Points fm = forces(model, (x - h * dx).eval(), zero);
    const Points derivative = (-(fp - fm) / (2 * h)).eval();
    EXPECT_LT((derivative - action).norm(), 1e-6 * action.norm());
  }
}

// Volumetric locking, the reason for the model: Lame's thick-walled cylinder in plane strain, a
// quarter of it (inner radius a, outer b) under an inner pressure p, whose radial displacement is
//   u_r(r) = (1 + nu) p a^2 / (E (b^2 - a^2)) ((1 - 2 nu) r + b^2 / r)
// (Timoshenko and Goodier, Theory of Elasticity, section 28; plane strain held on the end faces).
// It stays finite as nu -> 1/2, where plain linear tets lock: their every element must keep its
// volume, and too few motions are left.
struct Cylinder {
  Real inner = 0;     // u_r at r = a, the mean over the inner nodes [m]
  Real expected = 0;  // the closed form there [m]
};

Cylinder pressurised_cylinder(bool nodal, Real poisson_ratio) {
  const Real a = 0.01, b = 0.02, height = 0.0025, youngs = 3000, pressure = 0.3;
  // A box in (s, phi, z) mapped to r = a + s: positively oriented (the map's Jacobian is r).
  TetMesh mesh = make_box_mesh(Vec3(b - a, std::numbers::pi / 2, height), Vec3i(4, 8, 2));
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Real r = a + mesh.rest(n, 0), phi = mesh.rest(n, 1);
    mesh.rest.row(n) = Vec3(r * std::cos(phi), r * std::sin(phi), mesh.rest(n, 2)).transpose();
  }
  mesh.x = mesh.rest;
  const std::vector<ElementMaterial> materials = {{youngs, poisson_ratio, 1000, 0}};
  std::unique_ptr<Model> model;
  if (nodal) {
    model = std::make_unique<NodalPressureFem>(mesh, materials);
  } else {
    model = std::make_unique<CorotationalFem>(mesh, materials, RotationExtraction::polar);
  }
  // Plane strain (every z held), symmetry on the cut faces (y = 0: y held; x = 0: x held).
  Prescribed held;
  held.mask = AxisMask::Zero(mesh.num_nodes(), 3);
  held.position = mesh.rest;
  const auto radius = [&](int n) { return mesh.rest.row(n).head<2>().norm(); };
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (mesh.rest(n, 2) < 1e-12 || mesh.rest(n, 2) > height - 1e-12) held.mask(n, 2) = 1;
    if (std::abs(mesh.rest(n, 1)) < 1e-12) held.mask(n, 1) = 1;
    if (std::abs(mesh.rest(n, 0)) < 1e-12) held.mask(n, 0) = 1;
  }
  // The pressure on the inner faces, a third of each face's force on each of its nodes.
  Points load = Points::Zero(mesh.num_nodes(), 3);
  const BoundarySurface surface = boundary_surface(mesh);
  for (Eigen::Index f = 0; f < surface.faces.rows(); ++f) {
    std::array<int, 3> n{};
    for (int k = 0; k < 3; ++k)
      n[static_cast<std::size_t>(k)] = surface.nodes[static_cast<std::size_t>(surface.faces(f, k))];
    if (!(radius(n[0]) < a + 1e-9 && radius(n[1]) < a + 1e-9 && radius(n[2]) < a + 1e-9)) continue;
    const Vec3 p0 = row3(mesh.rest, n[0]), p1 = row3(mesh.rest, n[1]), p2 = row3(mesh.rest, n[2]);
    Vec3 area = 0.5 * (p1 - p0).cross(p2 - p0);
    const Vec3 centre = (p0 + p1 + p2) / 3;
    if (area.dot(Vec3(centre.x(), centre.y(), 0)) < 0) area = -area;  // push outwards from the axis
    for (const int node : n)
      load.row(node) += (pressure / 3 * area).transpose();
  }
  StaticSettings settings;
  settings.linear.solver = LinearSolver::assembled_ldlt;
  settings.tolerance = 1e-7;  // at nu 0.4999 round-off stalls Newton near 1e-9
  settings.max_iterations = 100;
  StaticSolver solver(settings);
  Points x = mesh.rest;
  const StaticReport report = solver.solve(Vec3::Zero(), load, held, *model, x);
  EXPECT_TRUE(report.converged) << model->name() << " nu " << poisson_ratio << " residual "
                                << report.relative_residual;
  Cylinder out;
  int inner = 0;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (radius(n) > a + 1e-9) continue;
    out.inner += x.row(n).head<2>().norm() - a;
    ++inner;
  }
  out.inner /= inner;
  out.expected = (1 + poisson_ratio) * pressure * a * a / (youngs * (b * b - a * a)) *
                 ((1 - 2 * poisson_ratio) * a + b * b / a);
  return out;
}

TEST(NodalPressureFem, ThickCylinderDoesNotLockAsNuApproachesOneHalf) {
  for (const Real nu : {0.3, 0.45, 0.499, 0.4999}) {
    const Cylinder nodal = pressurised_cylinder(true, nu);
    const Cylinder plain = pressurised_cylinder(false, nu);
    const Real nodal_error = std::abs(nodal.inner / nodal.expected - 1);
    const Real plain_error = std::abs(plain.inner / plain.expected - 1);
    RecordProperty("nu_" + std::to_string(nu), "nodal " + std::to_string(nodal_error) + ", plain " +
                                                   std::to_string(plain_error));
    EXPECT_LT(nodal_error, 0.06) << "nu " << nu << ": " << nodal.inner << " m against "
                                 << nodal.expected << " m";
    if (nu > 0.4995) {
      // The plain tet locks (measured: 24 % short at nu 0.4999, against 5 % here; at the liver's
      // nu 0.45 both are within 5 %: 2.8 % and 4.2 %).
      EXPECT_GT(plain_error, 0.15) << "nu " << nu;
    }
  }
}

}  // namespace
}  // namespace incise::sim::testing
