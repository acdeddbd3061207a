#include "sim/mesh/cgal/label_volume.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace incise::sim {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("label volume: " + what);
}

}  // namespace

void check_label_volume(const LabelVolume& volume) {
  require((volume.dims.array() >= 1).all(), "every dimension must be >= 1");
  require(volume.spacing.allFinite() && (volume.spacing.array() > 0).all(),
          "spacing must be finite and > 0 along every axis");
  require(volume.origin.allFinite(), "origin is not finite");
  require(
      volume.axes.allFinite() &&
          (volume.axes.transpose() * volume.axes - Mat3::Identity()).cwiseAbs().maxCoeff() <= 1e-6,
      "axes must be orthonormal columns (a rotation, or a rotation with a mirror)");
  const std::size_t count = static_cast<std::size_t>(volume.dims.x()) *
                            static_cast<std::size_t>(volume.dims.y()) *
                            static_cast<std::size_t>(volume.dims.z());
  require(volume.labels.size() == count, "labels has " + std::to_string(volume.labels.size()) +
                                             " entries, dims need " + std::to_string(count));
  bool any_tissue = false;
  for (std::uint8_t l : volume.labels)
    any_tissue = any_tissue || l != 0;
  require(any_tissue, "every voxel is 0 (outside): there is no tissue to mesh");
}

Box3 label_volume_extent(const LabelVolume& volume) {
  // The voxels span [-1/2, dims - 1/2] voxel steps along each of their axes.
  const Vec3 span = volume.dims.cast<Real>().cwiseProduct(volume.spacing);
  const Vec3 first = -volume.spacing / 2;
  Box3 box;
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 local = first;
    for (int a = 0; a < 3; ++a)
      if ((corner >> a) & 1) local[a] += span[a];
    box.extend(volume.origin + volume.axes * local);
  }
  return box;
}

int label_at(const LabelVolume& volume, const Vec3& p) {
  const Vec3 t = (volume.axes.transpose() * (p - volume.origin)).cwiseQuotient(volume.spacing);
  if (!t.allFinite()) return 0;
  const Vec3 base = t.array().floor();
  const Vec3 frac = t - base;
  // Up to 8 distinct labels with their summed weights.
  std::array<int, 8> label{};
  std::array<Real, 8> weight{};
  int used = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3i offset((corner >> 0) & 1, (corner >> 1) & 1, (corner >> 2) & 1);
    Real w = 1;
    for (int a = 0; a < 3; ++a)
      w *= offset[a] ? frac[a] : 1 - frac[a];
    int value = 0;
    bool inside = true;
    Vec3i ijk;
    for (int a = 0; a < 3; ++a) {
      const Real c = base[a] + offset[a];
      inside = inside && c >= 0 && c < volume.dims[a];
      ijk[a] = inside ? static_cast<int>(c) : 0;
    }
    if (inside) {
      const std::size_t index =
          static_cast<std::size_t>(ijk.x()) +
          static_cast<std::size_t>(volume.dims.x()) *
              (static_cast<std::size_t>(ijk.y()) +
               static_cast<std::size_t>(volume.dims.y()) * static_cast<std::size_t>(ijk.z()));
      value = volume.labels[index];
    }
    int slot = 0;
    while (slot < used && label[slot] != value)
      ++slot;
    if (slot == used) {
      label[used] = value;
      weight[used] = 0;
      ++used;
    }
    weight[slot] += w;
  }
  int best = 0;
  for (int s = 1; s < used; ++s) {
    if (weight[s] > weight[best] || (weight[s] == weight[best] && label[s] < label[best])) best = s;
  }
  return label[best];
}

Real voxel_volume_of(const LabelVolume& volume, int label) {
  std::size_t count = 0;
  for (std::uint8_t l : volume.labels)
    count += l == label ? 1 : 0;
  return static_cast<Real>(count) * volume.spacing.prod();
}

}  // namespace incise::sim
