#include "sim/mesh/box_mesher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "sim/mesh/tet_adjacency.h"

namespace incise::sim {
namespace {

struct BoxCase {
  Vec3 size;
  Vec3i cells;
};

class BoxMesher : public ::testing::TestWithParam<BoxCase> {
 protected:
  const Vec3 size_ = GetParam().size;
  const Vec3i cells_ = GetParam().cells;
  const TetMesh mesh_ = make_box_mesh(size_, cells_);
  const int nx_ = cells_.x();
  const int ny_ = cells_.y();
  const int nz_ = cells_.z();
};

TEST_P(BoxMesher, NodeAndTetCounts) {
  EXPECT_EQ(mesh_.num_nodes(), (nx_ + 1) * (ny_ + 1) * (nz_ + 1));
  EXPECT_EQ(mesh_.num_tets(), 5 * nx_ * ny_ * nz_);
  EXPECT_EQ(mesh_.labels.size(), mesh_.num_tets());
  EXPECT_TRUE(mesh_.labels.isZero());
}

TEST_P(BoxMesher, NodesSitOnTheGridWithTheCornerAtTheOrigin) {
  for (int k = 0; k <= nz_; ++k) {
    for (int j = 0; j <= ny_; ++j) {
      for (int i = 0; i <= nx_; ++i) {
        const int node = i + (nx_ + 1) * (j + (ny_ + 1) * k);
        const Vec3 expected(size_.x() * i / nx_, size_.y() * j / ny_, size_.z() * k / nz_);
        EXPECT_LT((row3(mesh_.rest, node) - expected).norm(), 1e-15) << "node " << node;
      }
    }
  }
  EXPECT_EQ(Vec3(mesh_.rest.colwise().minCoeff().transpose()), Vec3::Zero());
  // Exactly, so that a selection drawn on the far faces needs no tolerance.
  EXPECT_EQ(Vec3(mesh_.rest.colwise().maxCoeff().transpose()), size_);
}

TEST_P(BoxMesher, EveryTetIsPositiveAndTheVolumesFillTheBox) {
  const VecX volumes = tet_volumes(mesh_.rest, mesh_.tets);
  // A cell's corner tets hold 1/6 of it, its central tet 1/3.
  const Real cell = size_.prod() / cells_.prod();
  for (Eigen::Index t = 0; t < volumes.size(); ++t) {
    EXPECT_GT(volumes(t), 0) << "tet " << t;
    EXPECT_TRUE(std::abs(volumes(t) - cell / 6) < 1e-12 * cell ||
                std::abs(volumes(t) - cell / 3) < 1e-12 * cell);
  }
  EXPECT_NEAR(volumes.sum(), size_.prod(), 1e-12 * size_.prod());
}

TEST_P(BoxMesher, FacesAreConformingAndOnlyTheBoxSurfaceIsBoundary) {
  // face_neighbours throws if a face is shared by more than two tets.
  const Triangles boundary = boundary_faces(mesh_.tets);
  EXPECT_EQ(boundary.rows(), 2 * 2 * (nx_ * ny_ + ny_ * nz_ + nx_ * nz_));
  // A face with one tet inside the box would be a crack between cells.
  for (Eigen::Index f = 0; f < boundary.rows(); ++f) {
    bool on_a_box_face = false;
    for (int a = 0; a < 3; ++a) {
      for (const Real plane : {0.0, size_(a)}) {
        bool all = true;
        for (int c = 0; c < 3; ++c)
          all = all && mesh_.rest(boundary(f, c), a) == plane;
        on_a_box_face = on_a_box_face || all;
      }
    }
    EXPECT_TRUE(on_a_box_face) << "boundary face " << f << " is inside the box";
  }
  const Tets neighbours = face_neighbours(mesh_.tets);
  EXPECT_EQ((neighbours.array() < 0).count(), boundary.rows());
}

TEST_P(BoxMesher, EdgesAreTheGridLinesPlusOneDiagonalPerGridFace) {
  const int axis_edges =
      nx_ * (ny_ + 1) * (nz_ + 1) + (nx_ + 1) * ny_ * (nz_ + 1) + (nx_ + 1) * (ny_ + 1) * nz_;
  const int face_diagonals = (nx_ + 1) * ny_ * nz_ + nx_ * (ny_ + 1) * nz_ + nx_ * ny_ * (nz_ + 1);
  const Edges edges = unique_edges(mesh_.tets);
  EXPECT_EQ(edges.rows(), axis_edges + face_diagonals);
  // Euler characteristic of a ball: V - E + F - T = 1.
  const Eigen::Index faces = (4 * mesh_.num_tets() + boundary_faces(mesh_.tets).rows()) / 2;
  EXPECT_EQ(mesh_.num_nodes() - edges.rows() + faces - mesh_.num_tets(), 1);
}

TEST_P(BoxMesher, DiagonalsJoinEvenNodes) {
  const Edges edges = unique_edges(mesh_.tets);
  const auto grid_parity = [&](int node) {
    const int i = node % (nx_ + 1);
    const int j = (node / (nx_ + 1)) % (ny_ + 1);
    const int k = node / ((nx_ + 1) * (ny_ + 1));
    return (i + j + k) % 2;
  };
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    const Vec3 d = row3(mesh_.rest, edges(e, 1)) - row3(mesh_.rest, edges(e, 0));
    const int axes_spanned = (d.array().abs() > 1e-12).count();
    ASSERT_LE(axes_spanned, 2) << "edge " << e << " crosses a cell";
    if (axes_spanned == 2) {
      EXPECT_EQ(grid_parity(edges(e, 0)), 0);
      EXPECT_EQ(grid_parity(edges(e, 1)), 0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Boxes, BoxMesher,
                         ::testing::Values(BoxCase{Vec3(1, 1, 1), Vec3i(1, 1, 1)},
                                           BoxCase{Vec3(0.1, 0.2, 0.3), Vec3i(2, 3, 4)},
                                           BoxCase{Vec3(0.07, 0.01, 0.03), Vec3i(7, 1, 3)},
                                           BoxCase{Vec3(0.04, 0.04, 0.04), Vec3i(4, 4, 4)}));

// The directions of the diagonals balance out: with even cell counts the "fabric" tensor
// sum over edges of d d^T / |d|^2 is diagonal, so the springs do not couple stretch to shear.
// (The 6-tet split around the main diagonal fails this: every diagonal leans the same way.)
TEST(BoxMesherSymmetry, EdgeDirectionsHaveNoShearBias) {
  for (const Vec3i& cells : {Vec3i(2, 2, 2), Vec3i(4, 2, 6)}) {
    const TetMesh mesh = make_box_mesh(Vec3(0.02, 0.03, 0.05), cells);
    const Edges edges = unique_edges(mesh.tets);
    Mat3 fabric = Mat3::Zero();
    for (Eigen::Index e = 0; e < edges.rows(); ++e) {
      const Vec3 d = (row3(mesh.rest, edges(e, 1)) - row3(mesh.rest, edges(e, 0))).normalized();
      fabric += d * d.transpose();
    }
    const Mat3 off_diagonal = fabric - Mat3(fabric.diagonal().asDiagonal());
    EXPECT_LT(off_diagonal.norm(), 1e-9 * fabric.norm()) << cells.transpose();
  }
}

TEST(BoxMesherErrors, RejectsNonPositiveSizesAndCellCounts) {
  EXPECT_THROW(make_box_mesh(Vec3(1, 0, 1), Vec3i(1, 1, 1)), std::invalid_argument);
  EXPECT_THROW(make_box_mesh(Vec3(1, -1, 1), Vec3i(1, 1, 1)), std::invalid_argument);
  EXPECT_THROW(make_box_mesh(Vec3(1, 1, 1), Vec3i(1, 0, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim
