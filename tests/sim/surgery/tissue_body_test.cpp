// The tissue's recovery from being turned inside out (TissueBody::recover_inverted): an inverted
// tet is pulled toward its rest shape, turned and placed where it is; held nodes stay.
#include "sim/surgery/tissue_body.h"

#include <gtest/gtest.h>

#include <vector>

#include "sim/mesh/box_mesher.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/stable_time_step.h"

namespace incise::sim::surgery {
namespace {

constexpr Real kDt = 1e-4;

ModelFactory corotational() {
  Scene scene;
  scene.material.model = MaterialModel::corotational;
  scene.material.youngs_modulus = 5000;
  scene.material.poisson_ratio = 0.3;
  scene.material.density = 1000;
  return [scene](const TetMesh& mesh) { return make_model(scene, mesh); };
}

TissueBody body(TetMesh mesh, std::vector<char> fixed) {
  return TissueBody(std::move(mesh), corotational(), std::move(fixed), kDt,
                    p_wave_speed(5000, 0.3, 1000), 0);
}

Real volume(const TetMesh& mesh, int tet) {
  return tet_volumes(mesh.x, mesh.tets.row(tet)).sum();
}

int inverted(const TetMesh& mesh) {
  const VecX volumes = tet_volumes(mesh.x, mesh.tets);
  return static_cast<int>((volumes.array() <= 0).count());
}

// One free tet with a node pushed through the opposite face: a full pull (fraction 1) puts it in
// its rest shape exactly, turned (every edge its rest length, its volume the rest volume) and
// stopped.
TEST(TissueBody, AFullPullGivesAnInvertedTetItsRestShape) {
  Points rest(4, 3);
  rest << 0, 0, 0, 0.01, 0, 0, 0, 0.01, 0, 0, 0, 0.01;
  Tets tets(1, 4);
  tets << 0, 1, 2, 3;
  TetMesh mesh = make_tet_mesh(rest, tets);
  mesh.x.row(3) << 0.002, 0.003, -0.006;  // through the face 0 1 2
  mesh.x.row(1) << 0.011, 0.001, 0.0005;
  mesh.v.setConstant(0.3);
  TissueBody tissue = body(mesh, std::vector<char>(4, 0));
  ASSERT_LT(volume(tissue.mesh(), 0), 0);

  EXPECT_EQ(tissue.recover_inverted(1.0), 1);
  const TetMesh& after = tissue.mesh();
  EXPECT_NEAR(volume(after, 0), tet_volumes(rest, tets).sum(), 1e-15);
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) {
      EXPECT_NEAR((after.x.row(a) - after.x.row(b)).norm(), (rest.row(a) - rest.row(b)).norm(),
                  1e-12);
    }
  }
  // Placed where it was: the centroid did not move.
  EXPECT_LT((after.x.colwise().mean() - mesh.x.colwise().mean()).norm(), 1e-15);
  EXPECT_EQ(after.v.cwiseAbs().maxCoeff(), 0);
  EXPECT_EQ(tissue.recover_inverted(1.0), 0);  // nothing inverted any more
}

// Two separate tets, both inverted, each its own part: a full pull gives each its own rest shape
// where it is. A tool's reach keeps a tet out of the pull, and a node a grasper holds (the mask)
// stays.
TEST(TissueBody, PartsAreFittedApartAndToolsAndGraspsAreRespected) {
  Points rest(8, 3);
  rest << 0, 0, 0, 0.01, 0, 0, 0, 0.01, 0, 0, 0, 0.01,  //
      0.1, 0, 0, 0.11, 0, 0, 0.1, 0.01, 0, 0.1, 0, 0.01;
  Tets tets(2, 4);
  tets << 0, 1, 2, 3, 4, 5, 6, 7;
  TetMesh mesh = make_tet_mesh(rest, tets);
  mesh.x.row(3) << 0.002, 0.003, -0.006;
  mesh.x.row(7) << 0.102, 0.003, -0.006;
  const Real rest_volume = tet_volumes(rest, tets.topRows(1)).sum();

  {  // both pulled, each to its own rest shape around its own centroid
    TissueBody tissue = body(mesh, std::vector<char>(8, 0));
    EXPECT_EQ(tissue.recover_inverted(1.0), 2);
    for (int t = 0; t < 2; ++t) {
      EXPECT_NEAR(volume(tissue.mesh(), t), rest_volume, 1e-15) << t;
      const Eigen::RowVector3d before = mesh.x.middleRows(4 * t, 4).colwise().mean();
      const Eigen::RowVector3d after = tissue.mesh().x.middleRows(4 * t, 4).colwise().mean();
      EXPECT_LT((after - before).norm(), 1e-15) << t;
    }
  }
  {  // a probe's tip ball over the second tet keeps it as it is
    TissueBody tissue = body(mesh, std::vector<char>(8, 0));
    const TissueBody::Segment probe{Vec3(0.1, 0, 0), Vec3(0.1, 0, 0), 0.004};
    EXPECT_EQ(tissue.recover_inverted(1.0, std::span(&probe, 1)), 1);
    EXPECT_GT(volume(tissue.mesh(), 0), 0);
    EXPECT_EQ(tissue.mesh().x.middleRows(4, 4), mesh.x.middleRows(4, 4));
  }
  {  // node 3 held by a grasp: it stays, and the rest of its tet is fitted around it
    TissueBody tissue = body(mesh, std::vector<char>(8, 0));
    AxisMask grasped = AxisMask::Zero(8, 3);
    grasped.row(3).setOnes();
    EXPECT_EQ(tissue.recover_inverted(1.0, {}, &grasped), 2);
    EXPECT_EQ(tissue.mesh().x.row(3), mesh.x.row(3));
    EXPECT_GT(volume(tissue.mesh(), 0), 0);
  }
}

// A block held at its base with a top corner pushed down through it: repeated partial pulls leave
// no tet inverted, and the held nodes never move.
TEST(TissueBody, PartialPullsUntangleABlockAndHeldNodesStay) {
  TetMesh mesh = make_box_mesh(Vec3(0.02, 0.02, 0.02), Vec3i(2, 2, 2));
  std::vector<char> fixed(static_cast<std::size_t>(mesh.num_nodes()), 0);
  int corner = -1;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 2) == 0) fixed[static_cast<std::size_t>(i)] = 1;
    if (mesh.rest.row(i).isApprox(Eigen::RowVector3d(0.02, 0.02, 0.02))) corner = i;
  }
  ASSERT_GE(corner, 0);
  mesh.x.row(corner) << 0.012, 0.013, 0.004;  // through the tets below it
  TissueBody tissue = body(mesh, fixed);
  ASSERT_GT(inverted(tissue.mesh()), 0);
  const Points held = tissue.mesh().x;
  int calls = 0;
  while (inverted(tissue.mesh()) > 0 && calls < 200) {
    EXPECT_GT(tissue.recover_inverted(0.25), 0);
    ++calls;
  }
  EXPECT_EQ(inverted(tissue.mesh()), 0) << "after " << calls << " pulls";
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (fixed[static_cast<std::size_t>(i)] != 0) {
      EXPECT_EQ(tissue.mesh().x.row(i), held.row(i));
    }
  }
}

}  // namespace
}  // namespace incise::sim::surgery
