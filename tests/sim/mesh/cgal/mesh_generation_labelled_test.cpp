#include "sim/mesh/cgal/mesh_generation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "mesh_checks.h"
#include "sim/mesh/tet_adjacency.h"

namespace incise::sim {
namespace {

using testing::criteria;
using testing::expect_valid;
using testing::labelled_volume;
using testing::num_components;
using testing::print_figures;

constexpr Real kPi = std::numbers::pi;

struct CubeWithBall {
  LabelVolume volume;
  Vec3 ball_centre;
  Real ball_radius;
};

CubeWithBall cube_with_ball() {
  constexpr int n = 24;       // voxels per side
  constexpr Real h = 0.0025;  // voxel size [m]
  CubeWithBall s;
  s.volume = LabelVolume{Vec3i(n, n, n), Vec3::Constant(h), Vec3(0.1, 0.2, 0.3), {}};
  s.ball_centre = s.volume.origin + Vec3::Constant((n - 1) * h / 2);
  s.ball_radius = 6 * h;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 p = s.volume.origin + h * Vec3(i, j, k);
        const bool in_cube = std::min({i, j, k}) >= 2 && std::max({i, j, k}) <= n - 3;
        const bool in_ball = (p - s.ball_centre).norm() < s.ball_radius;
        s.volume.labels.push_back(in_ball ? 2 : in_cube ? 1 : 0);
      }
  return s;
}

TEST(MeshLabelledVolume, TwoTissuesKeepTheirVolumesAndShareAnInterface) {
  const CubeWithBall s = cube_with_ball();
  const Real h = s.volume.spacing.x();
  const MeshingCriteria c = criteria(1.5 * h, h / 4);
  const TetMesh mesh = mesh_labelled_volume(s.volume, c);
  expect_valid(mesh, label_volume_extent(s.volume));
  EXPECT_EQ(num_components(mesh.tets), 1);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    EXPECT_TRUE(mesh.labels[t] == 1 || mesh.labels[t] == 2) << "tet " << t;
  }
  const Real v1 = labelled_volume(mesh.rest, mesh.tets, mesh.labels, 1);
  const Real v2 = labelled_volume(mesh.rest, mesh.tets, mesh.labels, 2);
  const Real ref1 = voxel_volume_of(s.volume, 1);
  const Real ref2 = voxel_volume_of(s.volume, 2);
  print_figures("labelled tissue 1 (cube minus ball)", mesh, v1, ref1);
  print_figures("labelled tissue 2 (ball)", mesh, v2, ref2);
  std::printf("[figures] ball: analytic %.6g\n", 4 * kPi / 3 * std::pow(s.ball_radius, 3));
  // Tolerance 5%: the mesh is inscribed in the smoothed voxel surfaces (label_at), which
  // themselves differ from the voxel count by a fraction of a voxel layer.
  EXPECT_NEAR(v2, ref2, 0.05 * ref2);
  EXPECT_NEAR(v1, ref1, 0.05 * ref1);

  // Each tet carries the tissue it lies in. Mesh_3 labels a tet by the tissue at its
  // circumcentre, which for a few flat tets along the interface lies across it from the
  // centroid; all others agree.
  int agree = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Vec3 centroid = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
      centroid += row3(mesh.rest, mesh.tets(t, k)) / 4;
    agree += label_at(s.volume, centroid) == mesh.labels[t] ? 1 : 0;
  }
  std::printf("[figures] labels agreeing with the tissue at the centroid: %d of %d tets\n", agree,
              mesh.num_tets());
  EXPECT_GE(agree, 0.99 * mesh.num_tets());

  // Faces shared by a tet of each tissue: the interface, near the ball's surface.
  const Tets neighbours = face_neighbours(mesh.tets);
  int interface_faces = 0;
  Real worst_offset = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      const int n = neighbours(t, k);
      if (n < 0 || mesh.labels[t] != 1 || mesh.labels[n] != 2) continue;
      ++interface_faces;
      for (int corner : kTetFaces[k]) {
        const Real r = (row3(mesh.rest, mesh.tets(t, corner)) - s.ball_centre).norm();
        worst_offset = std::max(worst_offset, std::abs(r - s.ball_radius));
      }
    }
  }
  std::printf("[figures] interface: %d faces, largest |r - R| = %.3g m (voxel %.3g m)\n",
              interface_faces, worst_offset, h);
  EXPECT_GT(interface_faces, 50);
  EXPECT_LT(worst_offset, h);
}

TEST(MeshLabelledVolume, AnisotropicVoxelsKeepTheirVolume) {
  // A box of tissue 3, 10 x 8 x 5 voxels of 2 x 2 x 4 mm, inside a one-voxel empty border.
  const Vec3 spacing(0.002, 0.002, 0.004);
  LabelVolume volume{Vec3i(12, 10, 7), spacing, Vec3(-0.01, 0, 0.02), {}};
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 12; ++i) {
        const bool inside = i >= 1 && i <= 10 && j >= 1 && j <= 8 && k >= 1 && k <= 5;
        volume.labels.push_back(inside ? 3 : 0);
      }
  const TetMesh mesh = mesh_labelled_volume(volume, criteria(0.004, 0.0005));
  expect_valid(mesh, label_volume_extent(volume));
  EXPECT_TRUE((mesh.labels.array() == 3).all());
  const Real reference = voxel_volume_of(volume, 3);
  const Real v = total_volume(mesh.rest, mesh.tets);
  print_figures("anisotropic box", mesh, v, reference);
  // The box's edges and corners are rounded (no sharp-feature protection): a few % below.
  EXPECT_LT(v, reference);
  EXPECT_GT(v, 0.95 * reference);
}

}  // namespace
}  // namespace incise::sim
