// Model::update_elements, the local topology change of remeshing (state transfer:
// masses and element data updated only where an operation touched, the invariants kept): a tet
// split 1-4 at an interior point and merged back, on every model. The reference is a model built
// from scratch on the same tets; the laws are those of model_laws_test.cpp.
#include <gtest/gtest.h>

#include <vector>

#include "model_fixtures.h"
#include "sim/mesh/box_mesher.h"
#include "sim/models/tet_elements.h"

namespace incise::sim::testing {
namespace {

// The slot view after splitting tet `t` of mesh at the rest point p (a new node): slot t holds the
// first sub-tet, three new slots the others.
struct Split {
  TetMesh slots;
  std::vector<char> alive;
  std::vector<int> changed;
};

Split split_tet(const TetMesh& mesh, int t, const Vec3& p) {
  Split s;
  s.slots = mesh;
  const int n = mesh.num_nodes();
  const int tets = mesh.num_tets();
  s.slots.rest.conservativeResize(n + 1, 3);
  s.slots.rest.row(n) = p.transpose();
  s.slots.x = s.slots.rest;
  s.slots.v = Points::Zero(n + 1, 3);
  s.slots.tets.conservativeResize(tets + 3, 4);
  s.slots.labels.conservativeResize(tets + 3);
  const Eigen::RowVector4i corners = mesh.tets.row(t);
  // Replacing corner k by the new node keeps the orientation.
  const int slot_of[4] = {t, tets, tets + 1, tets + 2};
  for (int k = 0; k < 4; ++k) {
    Eigen::RowVector4i sub = corners;
    sub(k) = n;
    s.slots.tets.row(slot_of[k]) = sub;
    s.slots.labels(slot_of[k]) = mesh.labels(t);
    s.changed.push_back(slot_of[k]);
  }
  s.alive.assign(static_cast<std::size_t>(tets + 3), 1);
  return s;
}

// The alive slots as an ordinary mesh (all node slots kept).
TetMesh compact(const TetMesh& slots, const std::vector<char>& alive) {
  TetMesh out = slots;
  int rows = 0;
  for (int t = 0; t < slots.num_tets(); ++t) {
    if (alive[static_cast<std::size_t>(t)] == 0) continue;
    out.tets.row(rows) = slots.tets.row(t);
    out.labels(rows) = slots.labels(t);
    ++rows;
  }
  out.tets.conservativeResize(rows, 4);
  out.labels.conservativeResize(rows);
  return out;
}

class LocalUpdate : public ::testing::TestWithParam<ModelFactory> {};

TEST_P(LocalUpdate, SplitAndMergeKeepMassesForcesAndLaws) {
  TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  for (int t = 0; t < mesh.num_tets(); ++t)
    mesh.labels(t) = t % 2;
  const auto materials = test_materials();
  auto model = GetParam().make(mesh, materials);
  const VecX masses_before = model->masses();
  const auto revision_before = model->topology_revision();

  // Split tet 7 at an interior point (barycentric 0.1, 0.2, 0.3, 0.4).
  const int t = 7;
  Vec3 p = Vec3::Zero();
  const Real weights[4] = {0.1, 0.2, 0.3, 0.4};
  for (int k = 0; k < 4; ++k)
    p += weights[k] * row3(mesh.rest, mesh.tets(t, k));
  const Split split = split_tet(mesh, t, p);
  model->update_elements(split.slots, split.alive, split.changed);
  EXPECT_NE(model->topology_revision(), revision_before);

  // Masses: those of a model built on the split mesh; the total is unchanged.
  auto reference = GetParam().make(compact(split.slots, split.alive), materials);
  const VecX& masses = model->masses();
  ASSERT_EQ(masses.size(), mesh.num_nodes() + 1);
  EXPECT_LT((masses - reference->masses()).cwiseAbs().maxCoeff(), 1e-15 * masses.maxCoeff());
  EXPECT_NEAR(masses.sum(), masses_before.sum(), 1e-14 * masses_before.sum());
  EXPECT_GT(masses(mesh.num_nodes()), 0);

  // The rest state stays force-free; a deformed state (the new node carried by the affine map
  // of its tet) gives the reference model's forces, with zero net force and torque.
  const Points zero = Points::Zero(split.slots.num_nodes(), 3);
  const Points at_rest = forces(*model, split.slots.rest, zero);
  EXPECT_LT(at_rest.cwiseAbs().maxCoeff(), 1e-12);
  Points x = split.slots.rest + random_points(split.slots.num_nodes(), 1e-3, 11);
  Points v = random_points(split.slots.num_nodes(), 1e-2, 12);
  const Points f = forces(*model, x, v);
  const Points f_reference = forces(*reference, x, v);
  const Real scale = f_reference.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0);
  EXPECT_LT((f - f_reference).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_LT(f.colwise().sum().norm(), 1e-12 * scale);
  if (GetParam().rotation_invariant) {
    Vec3 torque = Vec3::Zero();
    for (int i = 0; i < split.slots.num_nodes(); ++i)
      torque += row3(x, i).cross(row3(f, i));
    EXPECT_LT(torque.norm(), 1e-12 * scale * mesh_size(mesh));
  }

  // Merge back: slot t holds the original tet again, the three new slots are empty, the new
  // node has no tet left and exactly no mass.
  Split merged = split;
  merged.slots.tets.row(t) = mesh.tets.row(t);
  for (int k = 1; k < 4; ++k)
    merged.alive[static_cast<std::size_t>(mesh.num_tets() + k - 1)] = 0;
  model->update_elements(merged.slots, merged.alive, split.changed);
  EXPECT_EQ(model->masses()(mesh.num_nodes()), 0);
  EXPECT_LT((model->masses().head(mesh.num_nodes()) - masses_before).cwiseAbs().maxCoeff(),
            1e-15 * masses_before.maxCoeff());
  Points x_old = x.topRows(mesh.num_nodes());
  auto original = GetParam().make(mesh, materials);
  const Points f_merged = forces(*model, x, v);
  const Points f_original = forces(*original, x_old, v.topRows(mesh.num_nodes()));
  EXPECT_LT((f_merged.topRows(mesh.num_nodes()) - f_original).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_EQ(row3(f_merged, mesh.num_nodes()), Vec3::Zero());
}

// A bad new tet (inverted) is refused with the model as it was.
TEST_P(LocalUpdate, AnInvertedNewTetIsRefusedAndNothingChanges) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  auto model = GetParam().make(mesh, test_materials());
  const VecX masses_before = model->masses();
  TetMesh slots = mesh;
  std::swap(slots.tets(3, 0), slots.tets(3, 1));  // mirrored: negative rest volume
  const std::vector<char> alive(static_cast<std::size_t>(mesh.num_tets()), 1);
  const std::vector<int> changed{3};
  EXPECT_THROW(model->update_elements(slots, alive, changed), std::invalid_argument);
  EXPECT_EQ(model->masses(), masses_before);
  const Points at_rest = forces(*model, mesh.rest, Points::Zero(mesh.num_nodes(), 3));
  EXPECT_LT(at_rest.cwiseAbs().maxCoeff(), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(AllModels, LocalUpdate, ::testing::ValuesIn(all_models()),
                         [](const ::testing::TestParamInfo<ModelFactory>& info) {
                           return info.param.name;
                         });

}  // namespace
}  // namespace incise::sim::testing
