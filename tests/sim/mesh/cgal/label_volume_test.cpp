#include "sim/mesh/cgal/label_volume.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace incise::sim {
namespace {

// 4 x 3 x 2 voxels of 0.5 x 1 x 2 m from (1, 2, 3): label = 1 + i for i < 3, the last column 0.
LabelVolume columns() {
  LabelVolume v{Vec3i(4, 3, 2), Vec3(0.5, 1, 2), Vec3(1, 2, 3), {}};
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i)
        v.labels.push_back(static_cast<std::uint8_t>(i < 3 ? 1 + i : 0));
  return v;
}

Vec3 centre(const LabelVolume& v, int i, int j, int k) {
  return v.origin + Vec3(i, j, k).cwiseProduct(v.spacing);
}

TEST(LabelVolume, VoxelCentresCarryTheirOwnLabel) {
  const LabelVolume v = columns();
  check_label_volume(v);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i)
        EXPECT_EQ(label_at(v, centre(v, i, j, k)), i < 3 ? 1 + i : 0);
}

TEST(LabelVolume, BoundariesLieHalfWayBetweenVoxelCentres) {
  const LabelVolume v = columns();
  const Vec3 a = centre(v, 1, 1, 0);  // label 2
  const Vec3 b = centre(v, 2, 1, 0);  // label 3
  EXPECT_EQ(label_at(v, a + 0.49 * (b - a)), 2);
  EXPECT_EQ(label_at(v, a + 0.51 * (b - a)), 3);
  // Exactly half-way the tie goes to the smaller label.
  EXPECT_EQ(label_at(v, a + 0.5 * (b - a)), 2);
  // Outside the voxels: 0; half a voxel beyond the first centre is the boundary of the volume.
  EXPECT_EQ(label_at(v, centre(v, 0, 1, 0) - Vec3(0.24, 0, 0)), 1);
  EXPECT_EQ(label_at(v, centre(v, 0, 1, 0) - Vec3(0.26, 0, 0)), 0);
  EXPECT_EQ(label_at(v, Vec3(-100, 0, 0)), 0);
  EXPECT_EQ(label_at(v, Vec3(1e300, 0, 0)), 0);
}

TEST(LabelVolume, ExtentAndVoxelVolumes) {
  const LabelVolume v = columns();
  const Box3 box = label_volume_extent(v);
  EXPECT_TRUE(box.min().isApprox(Vec3(0.75, 1.5, 2)));
  EXPECT_TRUE(box.max().isApprox(Vec3(2.75, 4.5, 6)));
  EXPECT_DOUBLE_EQ(voxel_volume_of(v, 1), 6 * 1.0);  // 6 voxels of 0.5 * 1 * 2 m^3
  EXPECT_DOUBLE_EQ(voxel_volume_of(v, 0), 6 * 1.0);
  EXPECT_DOUBLE_EQ(voxel_volume_of(v, 9), 0);
}

TEST(LabelVolume, InvalidVolumesAreRejectedWithTheReason) {
  const auto message = [](const LabelVolume& v) {
    try {
      check_label_volume(v);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  LabelVolume v = columns();
  v.dims.y() = 0;
  EXPECT_NE(message(v).find("dimension"), std::string::npos);
  v = columns();
  v.spacing.z() = -1;
  EXPECT_NE(message(v).find("spacing"), std::string::npos);
  v = columns();
  v.origin.x() = INFINITY;
  EXPECT_NE(message(v).find("origin"), std::string::npos);
  v = columns();
  v.labels.pop_back();
  EXPECT_NE(message(v).find("23 entries, dims need 24"), std::string::npos);
  v = columns();
  std::fill(v.labels.begin(), v.labels.end(), 0);
  EXPECT_NE(message(v).find("no tissue"), std::string::npos);
  v = columns();
  v.axes(0, 1) = 0.1;  // i and j no longer perpendicular
  EXPECT_NE(message(v).find("orthonormal"), std::string::npos);
}

// A scan's own orientation: i along +y, j along -x, k along -z (a turn and a mirror).
TEST(LabelVolume, RotatedAxesCarryTheVoxelsWithThem) {
  LabelVolume v = columns();
  v.axes << 0, -1, 0, 1, 0, 0, 0, 0, -1;
  check_label_volume(v);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) {
        const Vec3 world = v.origin + v.axes * Vec3(i, j, k).cwiseProduct(v.spacing);
        EXPECT_EQ(label_at(v, world), i < 3 ? 1 + i : 0);
      }
  // Along i (now +y) the label changes at half a voxel; along world x it does not.
  const Vec3 c = v.origin + v.axes * Vec3(1, 1, 0).cwiseProduct(v.spacing);
  EXPECT_EQ(label_at(v, c + Vec3(0, 0.24, 0)), 2);
  EXPECT_EQ(label_at(v, c + Vec3(0, 0.26, 0)), 3);
  EXPECT_EQ(label_at(v, c + Vec3(0.4, 0, 0)), 2);
  // The extent: y from the origin's 2 - 0.25 over 4 x 0.5; x from 1 + 0.5 back over 3 x 1;
  // z from 3 + 1 down over 2 x 2.
  const Box3 box = label_volume_extent(v);
  EXPECT_TRUE(box.min().isApprox(Vec3(-1.5, 1.75, 0))) << box.min().transpose();
  EXPECT_TRUE(box.max().isApprox(Vec3(1.5, 3.75, 4))) << box.max().transpose();
}

}  // namespace
}  // namespace incise::sim
