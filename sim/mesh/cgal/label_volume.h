#pragma once

// A labelled voxel volume (a segmented scan): one tissue label per voxel, 0 = outside the body.

#include <cstdint>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim {

// Voxel (i, j, k) has its centre at origin + axes * ((i, j, k) .* spacing) and covers the box of
// size spacing around it along the axes (the usual image convention: origin is the first voxel's
// centre). axes holds the world directions of the voxel axes i, j, k as orthonormal columns: the
// identity for a volume aligned with the world, a rotation (or a rotation with a mirror, as many
// scanners store) for a scan's own orientation (a NIfTI affine, sim/mesh/nifti/).
struct LabelVolume {
  Vec3i dims;                        // voxels along x, y, z, each >= 1
  Vec3 spacing;                      // voxel size along x, y, z [m], each > 0
  Vec3 origin;                       // centre of voxel (0, 0, 0) [m]
  std::vector<std::uint8_t> labels;  // dims.prod() labels, x fastest: i + dims.x * (j + dims.y * k)
  Mat3 axes = Mat3::Identity();      // world directions of i, j, k (orthonormal columns)
};

// Throws std::invalid_argument naming the problem: a dimension < 1, a spacing <= 0 or not finite,
// an origin not finite, axes that are not orthonormal (to 1e-6), labels of the wrong size, or no
// voxel with a label other than 0.
void check_label_volume(const LabelVolume& volume);

// The axis-aligned box [m] around the voxels (with rotated axes, around their 8 outer corners).
Box3 label_volume_extent(const LabelVolume& volume);

// The tissue label at p [m], smoothed between voxel centres: each of the 8 voxel centres around p
// votes for its label with its trilinear weight, and the label with the largest total weight wins
// (voxels outside the volume vote 0). Tissue boundaries then pass half-way between voxel centres
// of different labels, without the staircase of nearest-voxel lookup, so a mesher need not
// resolve voxel steps. Ties go to the smaller label.
int label_at(const LabelVolume& volume, const Vec3& p);

// The volume [m^3] of the voxels carrying label: their count times the voxel volume.
Real voxel_volume_of(const LabelVolume& volume, int label);

}  // namespace incise::sim
