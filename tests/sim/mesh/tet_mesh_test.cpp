#include "sim/mesh/tet_mesh.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace incise::sim {
namespace {

const Vec3 kO(0, 0, 0);
const Vec3 kX(1, 0, 0);
const Vec3 kY(0, 1, 0);
const Vec3 kZ(0, 0, 1);

TEST(SignedVolume, CornerTetIsOneSixthAndFlipsWithOrientation) {
  EXPECT_DOUBLE_EQ(signed_volume(kO, kX, kY, kZ), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(signed_volume(kO, kY, kX, kZ), -1.0 / 6.0);
  EXPECT_DOUBLE_EQ(signed_volume(kX, kO, kY, kZ), -1.0 / 6.0);
  EXPECT_DOUBLE_EQ(signed_volume(kO, kX, kY, Vec3(0.3, 0.7, 0)), 0.0);  // flat
}

TEST(SignedVolume, ScalesWithTheProductOfAxisScalesAndIgnoresTranslation) {
  const Vec3 scale(2, 3, 4);
  const Vec3 shift(-1.5, 0.25, 7);
  const auto map = [&](const Vec3& p) { return Vec3(scale.cwiseProduct(p) + shift); };
  EXPECT_NEAR(signed_volume(map(kO), map(kX), map(kY), map(kZ)), 24.0 / 6.0, 1e-12);
}

TEST(TetVolumes, PerTetAndTotal) {
  Points points(5, 3);
  points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -2;
  Tets tets(2, 4);
  tets << 0, 1, 2, 3,  // +1/6
      0, 2, 1, 4;      // below the xy plane, reordered to stay positive: +2/6
  const VecX volumes = tet_volumes(points, tets);
  ASSERT_EQ(volumes.size(), 2);
  EXPECT_DOUBLE_EQ(volumes(0), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(volumes(1), 2.0 / 6.0);
  EXPECT_DOUBLE_EQ(total_volume(points, tets), 0.5);
}

TEST(MakeTetMesh, StartsAtRestWithDefaultLabels) {
  Points rest(4, 3);
  rest << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Tets tets(1, 4);
  tets << 0, 1, 2, 3;
  const TetMesh mesh = make_tet_mesh(rest, tets);
  EXPECT_EQ(mesh.num_nodes(), 4);
  EXPECT_EQ(mesh.num_tets(), 1);
  EXPECT_EQ(mesh.x, rest);
  EXPECT_TRUE(mesh.v.isZero(0));
  EXPECT_EQ(mesh.v.rows(), 4);
  ASSERT_EQ(mesh.labels.size(), 1);
  EXPECT_EQ(mesh.labels(0), 0);

  const TetMesh labelled = make_tet_mesh(rest, tets, Eigen::VectorXi::Constant(1, 7));
  EXPECT_EQ(labelled.labels(0), 7);
}

TEST(MakeTetMesh, RejectsBadIndicesRepeatedNodesAndLabelCount) {
  Points rest = Points::Zero(4, 3);
  Tets out_of_range(1, 4);
  out_of_range << 0, 1, 2, 4;
  EXPECT_THROW(make_tet_mesh(rest, out_of_range), std::invalid_argument);
  Tets negative(1, 4);
  negative << 0, -1, 2, 3;
  EXPECT_THROW(make_tet_mesh(rest, negative), std::invalid_argument);
  Tets repeated(1, 4);
  repeated << 0, 1, 1, 3;
  EXPECT_THROW(make_tet_mesh(rest, repeated), std::invalid_argument);
  Tets good(1, 4);
  good << 0, 1, 2, 3;
  EXPECT_THROW(make_tet_mesh(rest, good, Eigen::VectorXi::Zero(2)), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim
