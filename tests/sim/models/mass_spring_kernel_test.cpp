// The vectorised mass-spring kernels (mass_spring_model.cpp: four springs, or four tets' health,
// to a SIMD register) against the scalar spring of spring_force.h summed spring by spring: equal
// to round-off over the test meshes, with degenerate springs (two nodes on top of each other),
// inverted tets, and springs and tets that a local update killed. The laws (net force and torque
// zero, rigid invariance) run on this kernel in model_laws_test.cpp, since
// MassSpringModel::add_forces is it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "model_fixtures.h"
#include "sim/models/mass_spring_model.h"
#include "sim/models/spring_force.h"

namespace incise::sim::testing {
namespace {

struct Reference {
  Points f;
  ModelHealth health;
};

// Spring by spring and tet by tet, as the scalar code did.
Reference scalar_forces(const MassSpringModel& model, const TetMesh& mesh,
                        const std::vector<char>& alive, const Points& x, const Points& v) {
  Reference r{Points::Zero(x.rows(), 3), {}};
  for (Eigen::Index s = 0; s < model.springs().rows(); ++s) {
    if (!model.spring_alive()[static_cast<std::size_t>(s)]) continue;
    const int i = model.springs()(s, 0), j = model.springs()(s, 1);
    const SpringForce force =
        spring_force(row3(x, i), row3(x, j), row3(v, i), row3(v, j), model.stiffness()(s),
                     model.damping()(s), model.rest_lengths()(s));
    r.health.degenerate_elements += force.degenerate ? 1 : 0;
    r.f.row(i) += force.on_i.transpose();
    r.f.row(j) -= force.on_i.transpose();
  }
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (!alive[static_cast<std::size_t>(t)]) continue;
    const Real det = edge_matrix(x, mesh.tets, t).determinant();
    const Real rest = edge_matrix(mesh.rest, mesh.tets, t).determinant() / 6;
    r.health.inverted_elements += det <= 0 ? 1 : 0;
    r.health.degenerate_elements += std::abs(det) < 6e-6 * rest ? 1 : 0;
  }
  return r;
}

void expect_equal(MassSpringModel& model, const TetMesh& mesh, const std::vector<char>& alive,
                  const Points& x, const Points& v, const std::string& what) {
  Points f = Points::Zero(x.rows(), 3);
  model.add_forces(x, v, f);
  const Reference reference = scalar_forces(model, mesh, alive, x, v);
  const Real scale = reference.f.norm() + 1e-9;
  EXPECT_LE((f - reference.f).norm(), 1e-12 * scale) << what;
  EXPECT_EQ(model.health().inverted_elements, reference.health.inverted_elements) << what;
  EXPECT_EQ(model.health().degenerate_elements, reference.health.degenerate_elements) << what;
}

TEST(MassSpringKernel, EqualsTheScalarSpringsOnEveryTestMesh) {
  for (const NamedMesh& named : test_meshes()) {
    const TetMesh& mesh = named.mesh;
    MassSpringModel model(mesh, test_materials());
    const std::vector<char> alive(static_cast<std::size_t>(mesh.num_tets()), 1);
    const Real size = mesh_size(mesh);
    const Points v = random_points(mesh.num_nodes(), 0.3, 5);
    for (unsigned seed = 0; seed < 5; ++seed) {
      const Points x = mesh.rest + random_points(mesh.num_nodes(), 0.1 * size, 10 + seed);
      expect_equal(model, mesh, alive, x, v, named.name + " seed " + std::to_string(seed));
    }
    // Node 1 moved onto node 0: their spring has no direction (degenerate, no force), and the
    // tets they share are flat.
    Points x = mesh.rest;
    x.row(1) = x.row(0);
    expect_equal(model, mesh, alive, x, v, named.name + " collapsed");
    // Turned inside out: every tet inverted.
    expect_equal(model, mesh, alive, -mesh.rest, v, named.name + " inverted");
  }
}

TEST(MassSpringKernel, DeadSpringsAndTetsTakeNoPart) {
  // The 3x2x2 box with its first tet removed: the springs only it held die, and so does the
  // slot; neither may add a force or count in the health.
  TetMesh mesh = test_meshes()[0].mesh;
  MassSpringModel model(mesh, test_materials());
  std::vector<char> alive(static_cast<std::size_t>(mesh.num_tets()), 1);
  alive[0] = 0;
  const int changed[] = {0};
  model.update_elements(mesh, alive, changed);
  int dead_springs = 0;
  for (const char a : model.spring_alive())
    dead_springs += a ? 0 : 1;
  ASSERT_GT(dead_springs, 0);
  const Points x = mesh.rest + random_points(mesh.num_nodes(), 0.05 * mesh_size(mesh), 3);
  const Points v = random_points(mesh.num_nodes(), 0.3, 4);
  expect_equal(model, mesh, alive, x, v, "first tet dead");
}

}  // namespace
}  // namespace incise::sim::testing
