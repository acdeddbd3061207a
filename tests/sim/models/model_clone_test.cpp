// Model::clone: a deep copy, state included, over every model and test mesh. Stepped on from the
// same inputs, the copy and the original agree bit for bit (the corotational models' warm-started
// rotations and every linearisation are copied); changing the copy leaves the original alone.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <tuple>

#include "condensed_fixtures.h"
#include "model_fixtures.h"
#include "sim/models/hybrid_condensed_model.h"

namespace incise::sim::testing {
namespace {

bool same_bits(const Points& a, const Points& b) {
  return a.rows() == b.rows() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(Real)) == 0;
}

class ModelClone : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(ModelClone, ACopyStepsOnBitForBitAndIsIndependent) {
  const ModelFactory factory = all_models()[static_cast<std::size_t>(std::get<0>(GetParam()))];
  const TetMesh mesh = test_meshes()[static_cast<std::size_t>(std::get<1>(GetParam()))].mesh;
  const Real size = mesh_size(mesh);
  auto original = factory.make(mesh, test_materials());
  // A history: rotating, deforming states, so that warm starts and linearisations hold state.
  auto state = [&](int k) {
    return Points(
        rigidly_moved(
            mesh.rest,
            Eigen::AngleAxis<Real>(0.1 * k, Vec3(1, 1, 0).normalized()).toRotationMatrix(),
            Vec3(0.01, 0, 0)) +
        random_points(mesh.num_nodes(), 0.01 * size, 10 + static_cast<unsigned>(k)));
  };
  const Points v = random_points(mesh.num_nodes(), 0.2, 5);
  for (int k = 0; k < 3; ++k)
    forces(*original, state(k), v);
  original->prepare_stiffness(state(2));

  const auto copy = original->clone();
  EXPECT_EQ(copy->name(), original->name());
  EXPECT_EQ(copy->topology_revision(), original->topology_revision());
  const Points x = state(3);
  const Points from_original = forces(*original, x, v);
  const Points from_copy = forces(*copy, x, v);
  EXPECT_TRUE(same_bits(from_copy, from_original));
  Points k_original = Points::Zero(mesh.num_nodes(), 3), k_copy = k_original;
  original->add_stiffness_times(v, k_original);
  copy->add_stiffness_times(v, k_copy);
  EXPECT_TRUE(same_bits(k_copy, k_original));
  EXPECT_EQ(copy->potential_energy(x), original->potential_energy(x));

  // Softening or rebuilding the copy changes nothing in the original: it still agrees with a
  // second copy. (Not with its own last call: a warm start makes the next call at the same x
  // start elsewhere, equal only to round-off.)
  const auto witness = original->clone();
  if (copy->soften_element(0, 0.5)) {
    EXPECT_FALSE(same_bits(forces(*copy, x, v), from_original));
  }
  copy->update_topology(test_meshes()[1].mesh);
  EXPECT_NE(copy->topology_revision(), original->topology_revision());
  EXPECT_TRUE(same_bits(forces(*original, x, v), forces(*witness, x, v)));
}

TEST(ModelClone, TheCondensedModelsCopyOwnsItsOperationalModelAndSharesTheFarField) {
  const TetMesh mesh = condensed_box(4);
  HybridCondensedModel original(mesh, top_block(mesh, 0.012, 0.012), condensed_materials(),
                                make_corotational);
  const auto copy = original.clone();
  const Points x = mesh.rest + random_displacements(mesh.num_nodes(), 0.002, 7);
  const Points v = random_displacements(mesh.num_nodes(), 0.1, 8);
  const Points from_original = forces(original, x, v);
  EXPECT_TRUE(same_bits(forces(*copy, x, v), from_original));
  const auto* condensed = dynamic_cast<const HybridCondensedModel*>(copy.get());
  ASSERT_NE(condensed, nullptr);
  EXPECT_NE(&condensed->operational_model(), &original.operational_model());
  // The copy's operational model changes alone.
  const auto witness = original.clone();
  copy->update_topology(mesh);
  EXPECT_TRUE(same_bits(forces(original, x, v), forces(*witness, x, v)));
}

std::string name(const ::testing::TestParamInfo<std::tuple<int, int>>& info) {
  return all_models()[static_cast<std::size_t>(std::get<0>(info.param))].name + "_" +
         test_meshes()[static_cast<std::size_t>(std::get<1>(info.param))].name;
}

INSTANTIATE_TEST_SUITE_P(AllModelsAllMeshes, ModelClone,
                         ::testing::Combine(::testing::Range(0, 7), ::testing::Range(0, 4)), name);

}  // namespace
}  // namespace incise::sim::testing
