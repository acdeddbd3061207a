#include "sim/models/tet_elements.h"

#include <gtest/gtest.h>

#include <Eigen/Sparse>

#include <stdexcept>
#include <string>

#include "model_fixtures.h"
#include "sim/mesh/box_mesher.h"
#include "sim/models/mass_spring.h"
#include "sim/models/mass_spring_model.h"

namespace incise::sim::testing {
namespace {

// Sum of density V0 over the tets, label by label.
Real density_times_volume(const TetMesh& mesh, const std::vector<ElementMaterial>& materials) {
  const VecX volumes = tet_volumes(mesh.rest, mesh.tets);
  Real mass = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const int label = mesh.labels.size() == 0 ? 0 : mesh.labels(t);
    mass += materials[static_cast<std::size_t>(label)].density * volumes(t);
  }
  return mass;
}

TEST(TetElements, LumpedMassOfEveryModelIsDensityTimesVolume) {
  const auto materials = test_materials();
  for (const NamedMesh& m : test_meshes()) {
    const Real expected = density_times_volume(m.mesh, materials);
    for (const ModelFactory& factory : all_models()) {
      const auto model = factory.make(m.mesh, materials);
      EXPECT_NEAR(model->masses().sum(), expected, 1e-12 * expected) << m.name << factory.name;
      EXPECT_TRUE((model->masses().array() > 0).all()) << m.name << factory.name;
    }
  }
}

TEST(TetElements, ConsistentMassRowsSumToTheLumpedMasses) {
  const NamedMesh m = test_meshes()[3];
  const TetElements elements = make_tet_elements(m.mesh, test_materials());
  std::vector<Eigen::Triplet<Real>> triplets;
  add_consistent_mass_triplets(elements, triplets);
  const Eigen::Index n = 3 * m.mesh.num_nodes();
  Eigen::SparseMatrix<Real> mass(n, n);
  mass.setFromTriplets(triplets.begin(), triplets.end());
  const VecX row_sums = mass * VecX::Ones(n);
  for (int i = 0; i < m.mesh.num_nodes(); ++i) {
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(row_sums(3 * i + c), elements.masses(i), 1e-12 * elements.masses(i));
  }
  // Kinetic energy of a rigid translation: v^T M v = total mass |v|^2, as with lumped masses.
  VecX v = VecX::Zero(n);
  for (int i = 0; i < m.mesh.num_nodes(); ++i)
    v.segment<3>(3 * i) = Vec3(1, 2, 3);
  EXPECT_NEAR(v.dot(mass * v), elements.masses.sum() * 14, 1e-12 * elements.masses.sum() * 14);
}

TEST(TetElements, ShapeGradientsReproduceAnAffineDeformation) {
  const NamedMesh m = test_meshes()[3];
  const TetElements elements = make_tet_elements(m.mesh, test_materials());
  Mat3 a;
  a << 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, -0.2, 0.1, 1.3;
  const Points x = rigidly_moved(m.mesh.rest, a, Vec3(1, 2, 3));
  for (int t = 0; t < elements.num_tets(); ++t) {
    const Mat3 f =
        edge_matrix(x, elements.tets, t) * elements.rest_inverse[static_cast<std::size_t>(t)];
    EXPECT_LT((f - a).norm(), 1e-12);
    EXPECT_NEAR(elements.rest_volume(t) * 6,
                edge_matrix(m.mesh.rest, elements.tets, t).determinant(), 1e-18);
  }
}

TEST(TetElements, LameParametersInvertJoshiEquations1And2) {
  const Lame lame = lame_from_youngs(3000, 0.45);
  EXPECT_NEAR(lame.mu * (3 * lame.lambda + 2 * lame.mu) / (lame.lambda + lame.mu), 3000, 1e-9);
  EXPECT_NEAR(lame.lambda / (2 * lame.lambda + 2 * lame.mu), 0.45, 1e-15);
}

TEST(TetElements, BadInputGetsAPreciseError) {
  TetMesh mesh = test_meshes()[0].mesh;
  auto message = [&](const std::vector<ElementMaterial>& materials) -> std::string {
    try {
      make_tet_elements(mesh, materials);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  // Label 1 has no material.
  EXPECT_NE(message({{3000, 0.45, 1000, 0}}).find("tet 1 has label 1 without a material"),
            std::string::npos);
  EXPECT_NE(message({{3000, 0.5, 1000, 0}, {3000, 0.4, 1000, 0}}).find("label 0: Poisson"),
            std::string::npos);
  EXPECT_NE(message({{3000, 0.4, 1000, 0}, {3000, 0.4, 0, 0}}).find("label 1: density"),
            std::string::npos);
  EXPECT_NE(message({{-1, 0.4, 1000, 0}, {3000, 0.4, 1000, 0}}).find("Young"), std::string::npos);
  EXPECT_NE(message({{3000, 0.4, 1000, -1}, {3000, 0.4, 1000, 0}}).find("damping"),
            std::string::npos);
  // A tet inverted at rest.
  std::swap(mesh.tets(4, 0), mesh.tets(4, 1));
  EXPECT_NE(message(test_materials()).find("tet 4 has non-positive rest volume"),
            std::string::npos);
}

TEST(MassSpringModel, WithOneMaterialMatchesMassSpring) {
  const TetMesh mesh = make_box_mesh(Vec3(0.05, 0.03, 0.02), Vec3i(3, 2, 2));
  const MassSpring reference(mesh.rest, mesh.tets, {3000, 1000, 0.3});
  MassSpringModel model(mesh, {{3000, 0.3, 1000, 0.3}});
  EXPECT_LT((model.masses() - reference.masses()).norm(), 1e-15);
  EXPECT_LT((model.stiffness() - reference.stiffness()).norm(),
            1e-12 * reference.stiffness().norm());
  EXPECT_LT((model.damping() - reference.damping()).norm(), 1e-12 * reference.damping().norm());
  const Points x = mesh.rest + random_points(mesh.num_nodes(), 0.003, 3);
  const Points v = random_points(mesh.num_nodes(), 0.1, 4);
  Points expected = Points::Zero(x.rows(), 3);
  reference.add_forces(x, v, expected);
  EXPECT_LT((forces(model, x, v) - expected).norm(), 1e-12 * expected.norm());
}

TEST(Models, NamesAreTheSceneNames) {
  const TetMesh mesh = test_meshes()[1].mesh;
  std::vector<std::string> names;
  for (const ModelFactory& factory : all_models())
    names.emplace_back(factory.make(mesh, test_materials())->name());
  EXPECT_EQ(names, (std::vector<std::string>{"linear", "corotational", "corotational_polar",
                                             "corotational_nodal_pressure", "stvk", "neohookean",
                                             "mss", "mss"}));
}

}  // namespace
}  // namespace incise::sim::testing
