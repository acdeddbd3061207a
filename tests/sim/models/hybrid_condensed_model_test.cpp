// The hybrid condensed model (sim/models/hybrid_condensed_model.h): with a linear operational
// model it must reproduce the full linear FEM's statics exactly (static condensation is exact),
// obey the laws of a linear elastic body (no force from a translation or an infinitesimal
// rotation, symmetric K*, D* = beta K* for uniform damping), conserve the mass, and keep the
// condensed region fixed through topology changes.
#include <gtest/gtest.h>

#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "condensed_fixtures.h"
#include "sim/solve/static_solver.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim::testing {
namespace {

using SparseMatrix = Eigen::SparseMatrix<Real>;

// 6^3 cells: 343 nodes, 125 of them inside the box; the operational block is 2 x 2 x 2 cells.
constexpr int kCells = 6;
constexpr Real kSize = 0.04;
constexpr Real kHalfWidth = kSize / 6 + 1e-9;
constexpr Real kDepth = kSize / 3;

Points zeros(Eigen::Index rows) {
  return Points::Zero(rows, 3);
}

SparseMatrix stiffness_matrix(const Model& model, Eigen::Index nodes) {
  std::vector<Eigen::Triplet<Real>> triplets;
  model.add_stiffness_triplets(triplets);
  SparseMatrix k(3 * nodes, 3 * nodes);
  k.setFromTriplets(triplets.begin(), triplets.end());
  return k;
}

// Solves K u = f on the coordinates where free is true (the others held at u = 0).
VecX solve_free(const SparseMatrix& k, const VecX& f, const std::vector<char>& free) {
  std::vector<int> index(free.size(), -1);
  int count = 0;
  for (std::size_t d = 0; d < free.size(); ++d) {
    if (free[d] != 0) index[d] = count++;
  }
  std::vector<Eigen::Triplet<Real>> reduced;
  for (int c = 0; c < k.outerSize(); ++c) {
    for (SparseMatrix::InnerIterator it(k, c); it; ++it) {
      const int r = index[static_cast<std::size_t>(it.row())];
      const int cc = index[static_cast<std::size_t>(it.col())];
      if (r >= 0 && cc >= 0) reduced.emplace_back(r, cc, it.value());
    }
  }
  SparseMatrix a(count, count);
  a.setFromTriplets(reduced.begin(), reduced.end());
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(a);
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  VecX rhs(count);
  for (std::size_t d = 0; d < free.size(); ++d) {
    if (index[d] >= 0) rhs(index[d]) = f(static_cast<Eigen::Index>(d));
  }
  const VecX reduced_u = ldlt.solve(rhs);
  VecX u = VecX::Zero(f.size());
  for (std::size_t d = 0; d < free.size(); ++d) {
    if (index[d] >= 0) u(static_cast<Eigen::Index>(d)) = reduced_u(index[d]);
  }
  return u;
}

// add_stiffness_times, add_damping_times, the triplets and the system blocks of the model (built
// on the rest positions `rest`) are the same matrices.
void check_products_triplets_and_blocks(Model& model, const Points& rest) {
  Model* hybrid = &model;
  const int n = static_cast<int>(rest.rows());
  hybrid->prepare_stiffness(rest + random_displacements(n, 1e-3, 3));
  const SparseMatrix k = stiffness_matrix(*hybrid, n);
  std::vector<Eigen::Triplet<Real>> d_triplets;
  hybrid->add_damping_triplets(d_triplets);
  SparseMatrix d(3 * n, 3 * n);
  d.setFromTriplets(d_triplets.begin(), d_triplets.end());

  const Points dx = random_displacements(n, 1, 4);
  Points kdx = zeros(n), ddx = zeros(n);
  hybrid->add_stiffness_times(dx, kdx);
  hybrid->add_damping_times(dx, ddx);
  const VecX k_expected = k * flatten(dx);
  const VecX d_expected = d * flatten(dx);
  EXPECT_LE((flatten(kdx) - k_expected).norm(), 1e-12 * k_expected.norm());
  EXPECT_LE((flatten(ddx) - d_expected).norm(), 1e-12 * d_expected.norm());

  const Real b = 0.3, c = 0.7;
  std::vector<std::pair<int, int>> blocks;
  hybrid->system_blocks(blocks);
  std::vector<int> slots(blocks.size());
  for (std::size_t i = 0; i < slots.size(); ++i)
    slots[i] = static_cast<int>(9 * i);
  std::vector<Real> values(9 * blocks.size(), 0);
  hybrid->add_system_blocks(b, c, BlockTarget{values.data(), slots.data()});
  Eigen::MatrixXd assembled = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const Mat3 block = Eigen::Map<const Mat3>(values.data() + 9 * i);
    const auto [r, col] = blocks[i];
    assembled.block<3, 3>(3 * r, 3 * col) += block;
    if (r != col) assembled.block<3, 3>(3 * col, 3 * r) += block.transpose();
  }
  const Eigen::MatrixXd expected = Eigen::MatrixXd(b * d + c * k);
  EXPECT_LE((assembled - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
}

class HybridCondensed : public ::testing::Test {
 protected:
  void SetUp() override {
    mesh_ = condensed_box(kCells, kSize);
    operational_ = top_block(mesh_, kHalfWidth, kDepth);
  }
  std::unique_ptr<HybridCondensedModel> make(const RegionModelFactory& factory,
                                             const std::vector<ElementMaterial>& materials) const {
    return std::make_unique<HybridCondensedModel>(mesh_, operational_, materials, factory);
  }
  // Base (z = 0) held; on each top node a load with shear, so every axis is exercised.
  std::vector<char> free_of_base() const {
    std::vector<char> free(3 * static_cast<std::size_t>(mesh_.num_nodes()), 1);
    for (int i = 0; i < mesh_.num_nodes(); ++i) {
      if (mesh_.rest(i, 2) < 1e-12) std::fill_n(free.begin() + 3 * i, 3, char{0});
    }
    return free;
  }
  Points top_load() const {
    Points load = zeros(mesh_.num_nodes());
    for (int i = 0; i < mesh_.num_nodes(); ++i) {
      if (mesh_.rest(i, 2) > kSize - 1e-12) load.row(i) << 0.03, -0.02, -0.1;  // [N]
    }
    return load;
  }

  TetMesh mesh_;
  std::vector<char> operational_;
};

TEST_F(HybridCondensed, RegionsPartitionTheNodes) {
  const auto hybrid = make(make_linear, condensed_materials());
  const int n = mesh_.num_nodes();
  // The box's 5^3 inner grid nodes minus the operational block's: its nodes are 3 x 3 x 3 grid
  // nodes, of which the top layer is on the body's surface and the other two are inner.
  EXPECT_EQ(hybrid->interior_nodes().size(), 125u - 9u - 9u);
  for (const int i : hybrid->interior_nodes()) {
    EXPECT_GT(mesh_.rest(i, 0), 1e-12);
    EXPECT_LT(mesh_.rest(i, 2), kSize - 1e-12);
    EXPECT_EQ(hybrid->masses()(i), 0.0) << "condensed node " << i << " is not simulated";
  }
  for (int i = 0; i < n; ++i) {
    const bool condensed =
        std::binary_search(hybrid->interior_nodes().begin(), hybrid->interior_nodes().end(), i);
    if (!condensed) {
      EXPECT_GT(hybrid->masses()(i), 0.0) << "node " << i;
    }
  }
  EXPECT_EQ(hybrid->condensed_stiffness().rows(),
            3 * static_cast<Eigen::Index>(hybrid->retained_nodes().size()));
}

TEST_F(HybridCondensed, StaticsEqualTheFullLinearFem) {
  const auto materials = condensed_materials();
  const LinearFem full(mesh_, materials);
  const auto hybrid = make(make_linear, materials);
  const int n = mesh_.num_nodes();
  const Points load = top_load();
  const VecX f = flatten(load);

  const VecX u_full = solve_free(stiffness_matrix(full, n), f, free_of_base());
  std::vector<char> free = free_of_base();
  for (const int i : hybrid->interior_nodes())
    std::fill_n(free.begin() + 3 * i, 3, char{0});
  const VecX u_hybrid = solve_free(stiffness_matrix(*hybrid, n), f, free);

  const Real scale = u_full.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 1e-6);  // a real deformation: micrometres at least
  Points x = mesh_.rest;
  for (int i = 0; i < n; ++i) {
    if (hybrid->masses()(i) == 0) continue;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(u_hybrid(3 * i + a), u_full(3 * i + a), 1e-8 * scale) << "node " << i;
      x(i, a) += u_hybrid(3 * i + a);
    }
  }
  hybrid->recover_interior(x);
  for (const int i : hybrid->interior_nodes()) {
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(x(i, a) - mesh_.rest(i, a), u_full(3 * i + a), 1e-8 * scale) << "node " << i;
  }

  // The forces agree with K: at the full solution the hybrid's internal forces balance the load
  // on every free simulated coordinate.
  Points x_full = mesh_.rest + Eigen::Map<const Points>(u_full.data(), n, 3);
  Points residual = load;
  hybrid->add_forces(x_full, zeros(n), residual);
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (free[3 * static_cast<std::size_t>(i) + a] != 0) {
        EXPECT_NEAR(residual(i, a), 0.0, 1e-8 * 0.1) << "node " << i;
      }
    }
  }
  // E = u.K u / 2 = f.u / 2 at equilibrium (Clapeyron).
  EXPECT_NEAR(hybrid->potential_energy(x_full), 0.5 * f.dot(u_full), 1e-9 * f.dot(u_full));
}

// The solvers handle the hybrid through the Model interface alone: matrix-free CG (stiffness
// products, block diagonal from the system blocks) and the assembled LDLT (system blocks).
TEST_F(HybridCondensed, StaticSolverReachesTheFullSolution) {
  const auto materials = condensed_materials();
  const LinearFem full(mesh_, materials);
  const int n = mesh_.num_nodes();
  const VecX u_full = solve_free(stiffness_matrix(full, n), flatten(top_load()), free_of_base());
  const Real scale = u_full.cwiseAbs().maxCoeff();
  Prescribed base{AxisMask::Zero(n, 3), mesh_.rest};
  for (int i = 0; i < n; ++i) {
    if (mesh_.rest(i, 2) < 1e-12) base.mask.row(i).setOnes();
  }
  for (const LinearSolver solver : {LinearSolver::matrix_free_cg, LinearSolver::assembled_ldlt}) {
    const auto hybrid = make(make_linear, materials);
    StaticSettings settings;
    settings.tolerance = 1e-11;
    settings.linear.solver = solver;
    settings.linear.preconditioner = Preconditioner::block_jacobi;
    StaticSolver static_solver(settings);
    Points x = mesh_.rest;
    const StaticReport report = static_solver.solve(Vec3::Zero(), top_load(), base, *hybrid, x);
    ASSERT_TRUE(report.converged) << "solver " << static_cast<int>(solver);
    for (int i = 0; i < n; ++i) {
      if (hybrid->masses()(i) == 0) continue;
      for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(x(i, a) - mesh_.rest(i, a), u_full(3 * i + a), 1e-7 * scale) << "node " << i;
    }
  }
}

TEST_F(HybridCondensed, CondensedStiffnessIsSymmetricAndFreeOfRigidModes) {
  const auto hybrid = make(make_corotational, condensed_materials());
  const Eigen::MatrixXd& k = hybrid->condensed_stiffness();
  const Real k_scale = k.cwiseAbs().maxCoeff();
  EXPECT_LE((k - k.transpose()).cwiseAbs().maxCoeff(), 1e-12 * k_scale);
  const auto& retained = hybrid->retained_nodes();
  const Eigen::Index n_s = static_cast<Eigen::Index>(retained.size());
  // Translations exactly; infinitesimal rotations u = w x X too (a linear model's null space).
  for (int a = 0; a < 3; ++a) {
    VecX translation = VecX::Zero(3 * n_s);
    VecX rotation(3 * n_s);
    const Vec3 axis = Vec3::Unit(a);
    for (Eigen::Index k_node = 0; k_node < n_s; ++k_node) {
      translation(3 * k_node + a) = 1;
      rotation.segment<3>(3 * k_node) =
          axis.cross(row3(mesh_.rest, retained[static_cast<std::size_t>(k_node)]));
    }
    // Relative to |K*| |u|: what a mode outside the null space would give.
    EXPECT_LE((k * translation).norm(), 1e-12 * k.norm() * translation.norm()) << "axis " << a;
    EXPECT_LE((k * rotation).norm(), 1e-12 * k.norm() * rotation.norm()) << "axis " << a;
  }
}

TEST_F(HybridCondensed, TranslationAndRestAreForceFree) {
  const auto hybrid = make(make_corotational, condensed_materials());
  const int n = mesh_.num_nodes();
  const Real force_scale = 3e4 * kSize * kSize;  // E L^2: a unit strain's force [N]
  Points f = zeros(n);
  hybrid->add_forces(mesh_.rest, zeros(n), f);
  EXPECT_LE(f.cwiseAbs().maxCoeff(), 1e-12 * force_scale);
  // Moving rigidly at a constant velocity: no elastic and no damping force.
  Points x = mesh_.rest;
  x.rowwise() += Eigen::RowVector3d(0.01, -0.02, 0.005);
  Points v = zeros(n);
  v.rowwise() += Eigen::RowVector3d(0.3, 0.1, -0.2);
  f.setZero();
  hybrid->add_forces(x, v, f);
  EXPECT_LE(f.cwiseAbs().maxCoeff(), 1e-10 * force_scale);
}

// A linear body's internal forces have zero net force, and zero torque taken at the rest
// positions, for any displacement (linear_fem.h).
TEST_F(HybridCondensed, InternalForcesHaveZeroNetForceAndRestTorque) {
  const auto hybrid = make(make_linear, condensed_materials());
  const int n = mesh_.num_nodes();
  const Points x = mesh_.rest + random_displacements(n, 1e-3, 7);
  const Points v = random_displacements(n, 0.1, 8);
  Points f = zeros(n);
  hybrid->add_forces(x, v, f);
  Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
  Real scale = 0;
  for (int i = 0; i < n; ++i) {
    net += row3(f, i);
    torque += row3(mesh_.rest, i).cross(row3(f, i));
    scale += row3(f, i).norm();
  }
  ASSERT_GT(scale, 0);
  EXPECT_LE(net.norm(), 1e-12 * scale);
  EXPECT_LE(torque.norm(), 1e-12 * scale * kSize);
}

// f = -dE/dx: the central difference of the energy along a random direction against f . d,
// with a nonlinear operational model.
TEST_F(HybridCondensed, ForcesAreMinusTheEnergyGradient) {
  const auto hybrid = make(make_corotational, condensed_materials(0));
  const int n = mesh_.num_nodes();
  const Points x = mesh_.rest + random_displacements(n, 1e-3, 21);
  Points d = random_displacements(n, 1, 22);
  for (const int i : hybrid->interior_nodes())
    d.row(i).setZero();  // E does not depend on them
  const Real h = 1e-7;
  const Real slope =
      (hybrid->potential_energy(x + h * d) - hybrid->potential_energy(x - h * d)) / (2 * h);
  Points f = zeros(n);
  hybrid->add_forces(x, zeros(n), f);
  const Real f_dot_d = f.cwiseProduct(d).sum();
  EXPECT_NEAR(slope, -f_dot_d, 1e-6 * std::abs(f_dot_d));
}

// Explicit stepping through the Model interface: symplectic Euler, undamped, base held, from a
// random velocity field, keeps the total energy (kinetic + elastic) within a few percent over
// hundreds of periods of the highest mode (symplectic: bounded energy error, no drift) at a fifth
// of the stable step 2 / omega_max; omega_max^2 from power iteration on M^-1 K.
TEST_F(HybridCondensed, SymplecticEulerKeepsTheEnergyBounded) {
  const auto hybrid = make(make_corotational, condensed_materials(0));
  const int n = mesh_.num_nodes();
  const VecX& m = hybrid->masses();
  VecX inv_mass = VecX::Zero(n);
  for (int i = 0; i < n; ++i) {
    if (m(i) > 0 && mesh_.rest(i, 2) > 1e-12) inv_mass(i) = 1 / m(i);
  }
  Points y = random_displacements(n, 1, 31), ky = zeros(n);
  Real omega_squared = 0;
  for (int k = 0; k < 100; ++k) {
    for (int i = 0; i < n; ++i)
      y.row(i) *= inv_mass(i) > 0 ? 1 : 0;
    y /= y.norm();
    ky.setZero();
    hybrid->add_stiffness_times(y, ky);
    for (int i = 0; i < n; ++i)
      ky.row(i) *= inv_mass(i);
    omega_squared = ky.cwiseProduct(y).sum() / y.squaredNorm();
    y = ky;
  }
  const Real dt = 0.2 * 2 / std::sqrt(1.05 * omega_squared);

  Points x = mesh_.rest;
  Points v = random_displacements(n, 0.01, 32);  // [m/s]
  for (int i = 0; i < n; ++i)
    v.row(i) *= inv_mass(i) > 0 ? 1 : 0;
  const auto energy = [&] {
    Real kinetic = 0;
    for (int i = 0; i < n; ++i)
      kinetic += 0.5 * m(i) * v.row(i).squaredNorm();
    return kinetic + hybrid->potential_energy(x);
  };
  const Real start = energy();
  Points f = zeros(n);
  Real worst = 0, early = 0, late = 0;
  const int steps = 1500, window = 200;
  for (int step = 0; step < steps; ++step) {
    f.setZero();
    hybrid->add_forces(x, v, f);
    symplectic_euler_step(dt, Vec3::Zero(), inv_mass, Prescribed{}, f, x, v);
    const Real e = energy();
    worst = std::max(worst, std::abs(e - start));
    if (step < window) early += e / window;
    if (step >= steps - window) late += e / window;
  }
  ASSERT_TRUE(x.allFinite());
  // The measured energy oscillates by O(dt omega) around a conserved modified energy (about 6%
  // here, with every mode excited); its mean does not drift.
  EXPECT_LT(worst, 0.1 * start);
  EXPECT_LT(std::abs(late - early), 0.01 * start);
  hybrid->recover_interior(x);
  EXPECT_TRUE(x.allFinite());
}

TEST_F(HybridCondensed, TotalMassIsTheFullMeshMass) {
  for (const auto& materials : {condensed_materials(), condensed_materials(1e-3, 0)}) {
    const auto hybrid = make(make_corotational, materials);
    const Real full = make_tet_elements(mesh_, materials).masses.sum();
    EXPECT_NEAR(hybrid->masses().sum(), full, 1e-13 * full);
  }
}

// Guyan-reduced Kelvin-Voigt damping D* = [I; T]^T D [I; T]. It is linear in D, and for D = beta K
// it is beta K* (kept as the scalar): so the D* of beta on tissue 0 only plus that of beta on
// tissue 1 only (each through the general formula) must add up to beta K*. Each is symmetric and
// lets translations pass undamped.
TEST_F(HybridCondensed, CondensedDampingIsTheReducedViscosity) {
  const Real beta = 2e-3;
  const auto uniform = make(make_linear, condensed_materials(beta));
  const Eigen::MatrixXd& k = uniform->condensed_stiffness();
  const Real k_scale = beta * k.cwiseAbs().maxCoeff();
  const Eigen::MatrixXd d0 = make(make_linear, condensed_materials(beta, 0))->condensed_damping();
  const Eigen::MatrixXd d1 = make(make_linear, condensed_materials(0, beta))->condensed_damping();
  ASSERT_EQ(d0.rows(), k.rows());
  ASSERT_EQ(d1.rows(), k.rows());
  EXPECT_LE((d0 + d1 - beta * k).cwiseAbs().maxCoeff(), 1e-12 * k_scale);
  VecX translation = VecX::Zero(k.rows());
  for (Eigen::Index r = 0; r < translation.size(); r += 3)
    translation(r) = 1;
  for (const Eigen::MatrixXd* d : {&d0, &d1}) {
    const Real scale = d->cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 0.1 * k_scale);
    EXPECT_LE((*d - d->transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale);
    EXPECT_LE((*d * translation).norm(), 1e-12 * d->norm() * translation.norm());
  }
  const auto undamped = make(make_linear, condensed_materials(0));
  EXPECT_EQ(undamped->condensed_damping().size(), 0);
}

TEST_F(HybridCondensed, StiffnessProductsTripletsAndBlocksAgree) {
  // Uniform far-field damping (D* = beta K*) and mixed (D* kept).
  for (const auto& materials : {condensed_materials(), condensed_materials(1e-3, 3e-3)}) {
    const auto hybrid = make(make_corotational, materials);
    check_products_triplets_and_blocks(*hybrid, mesh_.rest);
  }
}
std::string thrown_message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST_F(HybridCondensed, BadInputThrowsAPreciseError) {
  const auto materials = condensed_materials();
  std::vector<char> short_flags(operational_.begin(), operational_.end() - 1);
  EXPECT_EQ(thrown_message([&] {
              HybridCondensedModel{mesh_, short_flags, materials, make_linear};
            }),
            "HybridCondensedModel: operational flags must have one entry per tet (got 1079 for "
            "1080 tets)");
  const std::vector<char> none(operational_.size(), 0);
  EXPECT_EQ(thrown_message([&] {
              HybridCondensedModel{mesh_, none, materials, make_linear};
            }),
            "HybridCondensedModel: no operational tet (flag at least one tet operational)");
  EXPECT_EQ(thrown_message([&] {
              HybridCondensedModel{mesh_, operational_, materials, nullptr};
            }),
            "HybridCondensedModel: no operational model factory");
  const std::vector<ElementMaterial> one_material(materials.begin(), materials.begin() + 1);
  EXPECT_NE(thrown_message([&] {
              HybridCondensedModel{mesh_, operational_, one_material, make_linear};
            }),
            "(nothing thrown)");  // label 1 has no material: make_tet_elements names it
}

TEST_F(HybridCondensed, OperationalTopologyChangesLocallyAndTheFarFieldStaysFixed) {
  const auto materials = condensed_materials();
  auto hybrid = make(make_corotational, materials);
  const TetElements elements = make_tet_elements(mesh_, materials);
  const int op_tet = static_cast<int>(std::find(operational_.begin(), operational_.end(), 1) -
                                      operational_.begin());
  const int far_tet = static_cast<int>(std::find(operational_.begin(), operational_.end(), 0) -
                                       operational_.begin());
  const Real mass = hybrid->masses().sum();
  const auto revision = hybrid->topology_revision();

  // Removing an operational tet takes exactly its mass away.
  std::vector<char> alive(operational_.size(), 1);
  alive[static_cast<std::size_t>(op_tet)] = 0;
  const int changed[] = {op_tet};
  hybrid->update_elements(mesh_, alive, changed);
  const Real tet_mass = elements.density(op_tet) * elements.rest_volume(op_tet);
  EXPECT_NEAR(hybrid->masses().sum(), mass - tet_mass, 1e-13 * mass);
  EXPECT_NE(hybrid->topology_revision(), revision);

  // The far field is fixed: changing or killing one of its slots throws, model unchanged.
  const int far_changed[] = {far_tet};
  EXPECT_EQ(thrown_message([&] { hybrid->update_elements(mesh_, alive, far_changed); }),
            "HybridCondensedModel: update_elements: slot " + std::to_string(far_tet) +
                " is in the condensed region, which is fixed");
  std::vector<char> far_dead = alive;
  far_dead[static_cast<std::size_t>(far_tet)] = 0;
  EXPECT_EQ(thrown_message([&] { hybrid->update_elements(mesh_, far_dead, changed); }),
            "HybridCondensedModel: update_elements: far-field slot " + std::to_string(far_tet) +
                " is not alive (the condensed region is fixed)");
  EXPECT_NEAR(hybrid->masses().sum(), mass - tet_mass, 1e-13 * mass);

  // A new tet on a condensed interior node is refused.
  TetMesh grown = mesh_;
  grown.tets.conservativeResize(mesh_.num_tets() + 1, 4);
  grown.labels.conservativeResize(mesh_.num_tets() + 1);
  const int condensed_node = hybrid->interior_nodes().front();
  grown.tets.row(mesh_.num_tets()) = mesh_.tets.row(op_tet);
  grown.tets(mesh_.num_tets(), 0) = condensed_node;
  grown.labels(mesh_.num_tets()) = 0;
  std::vector<char> grown_alive = alive;
  grown_alive.push_back(1);
  const int new_slot[] = {mesh_.num_tets()};
  EXPECT_EQ(thrown_message([&] { hybrid->update_elements(grown, grown_alive, new_slot); }),
            "HybridCondensedModel: operational tet " + std::to_string(mesh_.num_tets()) +
                " uses condensed interior node " + std::to_string(condensed_node));

  // Putting the removed tet back in a new slot restores the mass and the forces.
  grown.tets.row(mesh_.num_tets()) = mesh_.tets.row(op_tet);
  grown.labels(mesh_.num_tets()) = mesh_.labels(op_tet);
  hybrid->update_elements(grown, grown_alive, new_slot);
  EXPECT_NEAR(hybrid->masses().sum(), mass, 1e-13 * mass);
  const int n = mesh_.num_nodes();
  const Points x = mesh_.rest + random_displacements(n, 1e-3, 11);
  const auto reference = make(make_corotational, materials);
  Points f = zeros(n), f_reference = zeros(n);
  hybrid->add_forces(x, zeros(n), f);
  reference->add_forces(x, zeros(n), f_reference);
  EXPECT_LE((f - f_reference).cwiseAbs().maxCoeff(), 1e-12 * f_reference.cwiseAbs().maxCoeff());

  // update_topology finds the far field by its tets in any row and node order.
  TetMesh shuffled = mesh_;
  shuffled.tets.colwise().reverseInPlace();
  for (int t = 0; t < shuffled.num_tets(); ++t) {
    std::swap(shuffled.tets(t, 0), shuffled.tets(t, 1));  // keep a positive orientation...
    std::swap(shuffled.tets(t, 2), shuffled.tets(t, 3));  // ...with an even permutation
  }
  shuffled.labels.reverseInPlace();
  hybrid->update_topology(shuffled);
  Points f_shuffled = zeros(n);
  hybrid->add_forces(x, zeros(n), f_shuffled);
  EXPECT_LE((f_shuffled - f_reference).cwiseAbs().maxCoeff(),
            1e-12 * f_reference.cwiseAbs().maxCoeff());
  TetMesh without_far = mesh_;
  without_far.tets.row(far_tet) = mesh_.tets.row(op_tet);
  EXPECT_NE(thrown_message([&] { hybrid->update_topology(without_far); }).find("is missing"),
            std::string::npos);
}

}  // namespace
}  // namespace incise::sim::testing
