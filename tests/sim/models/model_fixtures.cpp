#include "model_fixtures.h"

#include <random>

#include "sim/mesh/box_mesher.h"
#include "sim/models/corotational_fem.h"
#include "sim/models/linear_fem.h"
#include "sim/models/mass_spring_model.h"
#include "sim/models/neo_hookean_fem.h"
#include "sim/models/nodal_pressure_fem.h"
#include "sim/models/stvk_fem.h"

namespace incise::sim::testing {

Points random_points(Eigen::Index rows, Real scale, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<Real> uniform(-scale, scale);
  Points points(rows, 3);
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (int a = 0; a < 3; ++a)
      points(i, a) = uniform(random);
  }
  return points;
}

Mat3 random_rotation(unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<Real> normal;
  Eigen::Quaternion<Real> q(normal(random), normal(random), normal(random), normal(random));
  return q.normalized().toRotationMatrix();
}

Real mesh_size(const TetMesh& mesh) {
  return (mesh.rest.colwise().maxCoeff() - mesh.rest.colwise().minCoeff()).norm();
}

Points rigidly_moved(const Points& rest, const Mat3& rotation, const Vec3& shift) {
  Points x(rest.rows(), 3);
  for (Eigen::Index i = 0; i < rest.rows(); ++i)
    x.row(i) = (rotation * rest.row(i).transpose() + shift).transpose();
  return x;
}

VecX flat(const Points& p) {
  return Eigen::Map<const VecX>(p.data(), p.size());
}

Points forces(Model& model, const Points& x, const Points& v) {
  Points f = Points::Zero(x.rows(), 3);
  model.add_forces(x, v, f);
  return f;
}

namespace {

TetMesh single_tet(const Points& nodes) {
  Tets tets(1, 4);
  tets << 0, 1, 2, 3;
  return make_tet_mesh(nodes, tets);
}

void alternate_labels(TetMesh& mesh) {
  mesh.labels.resize(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t)
    mesh.labels(t) = t % 2;
}

}  // namespace

std::vector<NamedMesh> test_meshes() {
  std::vector<NamedMesh> meshes;
  TetMesh box = make_box_mesh(Vec3(0.05, 0.04, 0.03), Vec3i(3, 2, 2));
  alternate_labels(box);
  meshes.push_back({"box", box});

  Points corner(4, 3);
  corner << 0, 0, 0, 0.02, 0, 0, 0, 0.02, 0, 0, 0, 0.02;
  meshes.push_back({"single_tet", single_tet(corner)});

  // a, b, c, d nearly on the plane z = 0, spread as a square: dihedral angles near 0 and 180.
  Points sliver(4, 3);
  sliver << 0, 0, 0, 0.02, 0, 0, 0, 0.02, 0, 0.02, 0.02, 0.0004;
  meshes.push_back({"sliver", single_tet(sliver)});

  TetMesh jittered = make_box_mesh(Vec3(0.04, 0.04, 0.03), Vec3i(3, 3, 2));
  const Real cell = 0.01;
  jittered.rest += random_points(jittered.num_nodes(), 0.2 * cell, 7);
  jittered.x = jittered.rest;
  alternate_labels(jittered);
  meshes.push_back({"jittered_box", jittered});
  return meshes;
}

std::vector<ElementMaterial> test_materials(Real poisson_ratio) {
  return {{3000, poisson_ratio, 1000, 0.01}, {12000, poisson_ratio * 0.5, 1100, 0.02}};
}

std::vector<ModelFactory> all_models() {
  using Materials = std::vector<ElementMaterial>;
  return {
      {"linear", false,
       [](const TetMesh& m, const Materials& mat) { return std::make_unique<LinearFem>(m, mat); }},
      {"corotational_qr", true,
       [](const TetMesh& m, const Materials& mat) {
         return std::make_unique<CorotationalFem>(m, mat, RotationExtraction::qr);
       }},
      {"corotational_polar", true,
       [](const TetMesh& m, const Materials& mat) {
         return std::make_unique<CorotationalFem>(m, mat, RotationExtraction::polar);
       }},
      {"corotational_nodal_pressure", true,
       [](const TetMesh& m, const Materials& mat) {
         return std::make_unique<NodalPressureFem>(m, mat);
       }},
      {"stvk", true,
       [](const TetMesh& m, const Materials& mat) {
         return std::make_unique<StVenantKirchhoffFem>(m, mat);
       }},
      {"neohookean", true,
       [](const TetMesh& m, const Materials& mat) {
         return std::make_unique<NeoHookeanFem>(m, mat);
       }},
      {"mss", true,
       [](const TetMesh& m, const Materials& mat) {
         return std::make_unique<MassSpringModel>(m, mat);
       }},
      {"mss_volume", true,
       [](const TetMesh& m, const Materials& mat) {
         return std::make_unique<MassSpringModel>(m, mat, 2.0);
       }},
  };
}

}  // namespace incise::sim::testing
