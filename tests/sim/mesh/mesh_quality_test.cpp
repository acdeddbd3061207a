#include "sim/mesh/mesh_quality.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "sim/mesh/box_mesher.h"

namespace incise::sim {
namespace {

constexpr Real kPi = std::numbers::pi;
constexpr Real kTol = 1e-12;

// The regular tet on alternate corners of the cube [-1, 1]^3 (edge 2 sqrt 2), positively
// oriented, volume 8/3.
TetQuality regular(Real scale = 1) {
  return tet_quality(scale * Vec3(1, 1, 1), scale * Vec3(-1, 1, -1), scale * Vec3(1, -1, -1),
                     scale * Vec3(-1, -1, 1));
}

TEST(MeshQuality, RegularTet) {
  const TetQuality q = regular();
  EXPECT_NEAR(q.volume, 8.0 / 3, kTol);
  EXPECT_NEAR(q.longest_edge, 2 * std::sqrt(2.0), kTol);
  EXPECT_NEAR(q.aspect_ratio, 1, kTol);
  EXPECT_NEAR(q.min_dihedral, std::acos(1.0 / 3), kTol);
  EXPECT_NEAR(q.max_dihedral, std::acos(1.0 / 3), kTol);
  EXPECT_FALSE(is_degenerate(q));
}

TEST(MeshQuality, ScaleInvariantAndMirrorOnlyFlipsTheVolumeSign) {
  const TetQuality small = regular(1e-3);
  EXPECT_NEAR(small.volume, 8.0 / 3 * 1e-9, 1e-20);
  EXPECT_NEAR(small.aspect_ratio, 1, kTol);
  // Swapping two nodes mirrors the tet.
  const TetQuality mirrored =
      tet_quality(Vec3(-1, 1, -1), Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, -1, 1));
  EXPECT_NEAR(mirrored.volume, -8.0 / 3, kTol);
  EXPECT_NEAR(mirrored.aspect_ratio, 1, kTol);
  EXPECT_NEAR(mirrored.min_dihedral, std::acos(1.0 / 3), kTol);
}

TEST(MeshQuality, RightCornerTet) {
  // Three right angles at the origin; the slanted face meets the others at acos(1/sqrt 3).
  // Inradius 3V / A = (1/2) / (3/2 + sqrt(3)/2), longest edge sqrt 2:
  // aspect = sqrt 2 (3 + sqrt 3) / (2 sqrt 6) = (1 + sqrt 3) / 2.
  const TetQuality q = tet_quality(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1));
  EXPECT_NEAR(q.volume, 1.0 / 6, kTol);
  EXPECT_NEAR(q.aspect_ratio, (1 + std::sqrt(3.0)) / 2, kTol);
  EXPECT_NEAR(q.min_dihedral, std::acos(1 / std::sqrt(3.0)), kTol);
  EXPECT_NEAR(q.max_dihedral, kPi / 2, kTol);
}

TEST(MeshQuality, SliverHasDihedralsNearZeroAndPi) {
  // Two crossed edges of length 2 at heights +h and -h: volume 4h/3; the dihedral angle is
  // pi - 2 atan(2h) at the two crossed edges and acos(1 / (1 + 4h^2)) = atan(2h sqrt(2 + 4h^2))
  // at the four others. h = 1/sqrt 2 is the regular tet; h -> 0 flattens it to a square.
  for (const Real h : {1 / std::sqrt(2.0), 0.5, 1e-2, 1e-4}) {
    const TetQuality q =
        tet_quality(Vec3(1, 0, h), Vec3(-1, 0, h), Vec3(0, 1, -h), Vec3(0, -1, -h));
    EXPECT_NEAR(q.volume, 4 * h / 3, kTol) << h;
    EXPECT_NEAR(q.max_dihedral, kPi - 2 * std::atan(2 * h), kTol) << h;
    EXPECT_NEAR(q.min_dihedral, std::atan(2 * h * std::sqrt(2 + 4 * h * h)), kTol) << h;
    // Longest edge 2 (for h <= 1/sqrt 2), four faces of area sqrt(1 + 4h^2):
    // aspect = 2 * 4 sqrt(1 + 4h^2) / (6 sqrt 6 * 4h/3) = sqrt(1 + 4h^2) / (sqrt 6 h).
    const Real aspect = std::sqrt(1 + 4 * h * h) / (std::sqrt(6.0) * h);
    EXPECT_NEAR(q.aspect_ratio, aspect, 1e-12 * aspect) << h;
  }
  const Real h = 1e-4;
  const TetQuality q = tet_quality(Vec3(1, 0, h), Vec3(-1, 0, h), Vec3(0, 1, -h), Vec3(0, -1, -h));
  EXPECT_LT(q.min_dihedral, 1e-3);
  EXPECT_GT(q.max_dihedral, kPi - 1e-3);
  EXPECT_GT(q.aspect_ratio, 1e3);
}

TEST(MeshQuality, FlatTetIsDegenerateWithoutNaN) {
  const TetQuality q = tet_quality(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0));
  EXPECT_EQ(q.volume, 0);
  EXPECT_TRUE(is_degenerate(q));
  EXPECT_EQ(q.aspect_ratio, std::numeric_limits<Real>::infinity());
  EXPECT_NEAR(q.min_dihedral, 0, kTol);
  EXPECT_NEAR(q.max_dihedral, kPi, kTol);
  const TetQuality collapsed =
      tet_quality(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0));
  EXPECT_TRUE(is_degenerate(collapsed));
  EXPECT_FALSE(std::isnan(collapsed.min_dihedral));
  EXPECT_FALSE(std::isnan(collapsed.max_dihedral));
}

TEST(MeshQuality, SummaryCountsRangesAndHistograms) {
  // Regular, right-corner, inverted right-corner, flat.
  Points points(9, 3);
  points << 1, 1, 1, -1, 1, -1, 1, -1, -1, -1, -1, 1,  // regular: 0 1 2 3
      0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1,              // right corner: 4 5 6 7
      1, 1, 0;                                         // 8: in the plane z = 0 with 4 5 6
  Tets tets(4, 4);
  tets << 0, 1, 2, 3, 4, 5, 6, 7, 5, 4, 6, 7, 4, 5, 6, 8;
  const QualitySummary s = summarize_quality(points, tets);
  EXPECT_EQ(s.num_tets, 4);
  EXPECT_EQ(s.num_inverted, 1);
  EXPECT_EQ(s.num_degenerate, 1);
  EXPECT_NEAR(s.total_volume, 8.0 / 3, kTol);
  EXPECT_NEAR(s.volume.min, -1.0 / 6, kTol);
  EXPECT_NEAR(s.volume.max, 8.0 / 3, kTol);
  EXPECT_NEAR(s.volume.mean, 8.0 / 12, kTol);
  const Real corner = (1 + std::sqrt(3.0)) / 2;
  EXPECT_NEAR(s.aspect_ratio.min, 1, kTol);  // over the 3 non-degenerate tets
  EXPECT_NEAR(s.aspect_ratio.max, corner, kTol);
  EXPECT_NEAR(s.aspect_ratio.mean, (1 + 2 * corner) / 3, kTol);
  EXPECT_NEAR(s.min_dihedral.min, 0, kTol);
  EXPECT_NEAR(s.max_dihedral.max, kPi, kTol);
  // Aspect buckets: regular and both corners in [1, 1.5), the flat one in [10, inf].
  EXPECT_EQ(s.aspect_ratio_histogram, (std::array<int, 6>{3, 0, 0, 0, 0, 1}));
  // Min dihedral buckets [deg]: flat 0 -> [0, 5); corners 54.7 and regular 70.5 -> [50, 70.5].
  EXPECT_EQ(s.min_dihedral_histogram, (std::array<int, 7>{1, 0, 0, 0, 0, 0, 3}));
}

TEST(MeshQuality, BoxMeshSummaryMatchesItsGeometry) {
  const TetMesh mesh = make_box_mesh(Vec3(0.1, 0.15, 0.2), Vec3i(2, 3, 4));
  const QualitySummary s = summarize_quality(mesh.rest, mesh.tets);
  EXPECT_EQ(s.num_tets, mesh.num_tets());
  EXPECT_EQ(s.num_inverted, 0);
  EXPECT_EQ(s.num_degenerate, 0);
  EXPECT_NEAR(s.total_volume, 0.1 * 0.15 * 0.2, 1e-15);
  // Each cube cell (edge 0.05) is a central regular tet of a third of the cell and 4
  // right-corner tets of a sixth.
  const Real cell = 0.05 * 0.05 * 0.05;
  EXPECT_NEAR(s.volume.min, cell / 6, 1e-18);
  EXPECT_NEAR(s.volume.max, cell / 3, 1e-18);
  EXPECT_NEAR(s.aspect_ratio.min, 1, 1e-12);
  EXPECT_NEAR(s.aspect_ratio.max, (1 + std::sqrt(3.0)) / 2, 1e-12);
}

}  // namespace
}  // namespace incise::sim
