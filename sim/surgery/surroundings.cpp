#include "sim/surgery/surroundings.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace incise::sim::surgery {

namespace {
constexpr Real kPi = std::numbers::pi;
}  // namespace

Surrounding ellipsoid_surrounding(std::string name, SurroundingKind kind, const Vec3& centre,
                                  const Vec3& radii, int slices, int stacks) {
  if (slices < 3 || stacks < 2) {
    throw std::invalid_argument("ellipsoid_surrounding: needs slices >= 3 and stacks >= 2");
  }
  if (!(radii.minCoeff() > 0) || !radii.allFinite() || !centre.allFinite()) {
    throw std::invalid_argument("ellipsoid_surrounding: radii must be positive and finite");
  }
  Surrounding s;
  s.name = std::move(name);
  s.kind = kind;
  // Rings k = 1 .. stacks - 1 of slices vertices each, then the two poles.
  const int rings = stacks - 1;
  s.vertices.resize(rings * slices + 2, 3);
  for (int k = 1; k <= rings; ++k) {
    const Real polar = kPi * k / stacks;
    for (int i = 0; i < slices; ++i) {
      const Real azimuth = 2 * kPi * i / slices;
      const Vec3 unit(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                      std::cos(polar));
      s.vertices.row((k - 1) * slices + i) = (centre + radii.cwiseProduct(unit)).transpose();
    }
  }
  const int north = rings * slices, south = north + 1;
  s.vertices.row(north) = (centre + Vec3(0, 0, radii.z())).transpose();
  s.vertices.row(south) = (centre - Vec3(0, 0, radii.z())).transpose();
  const auto at = [slices](int ring, int i) { return ring * slices + (i % slices); };
  s.triangles.resize(2 * slices * rings, 3);
  int t = 0;
  for (int i = 0; i < slices; ++i) {
    s.triangles.row(t++) << north, at(0, i), at(0, i + 1);
    s.triangles.row(t++) << south, at(rings - 1, i + 1), at(rings - 1, i);
  }
  for (int k = 0; k + 1 < rings; ++k) {
    for (int i = 0; i < slices; ++i) {
      s.triangles.row(t++) << at(k, i), at(k + 1, i), at(k + 1, i + 1);
      s.triangles.row(t++) << at(k, i), at(k + 1, i + 1), at(k, i + 1);
    }
  }
  return s;
}

std::vector<Surrounding> liver_surroundings(const Box3& organ, Real flat_side_z) {
  const Vec3 c = organ.center();
  const Vec3 half = organ.sizes() / 2;
  // A millimetre below the flat side, so the organ never dips into the wall in the picture.
  constexpr Real kGap = 0.001;
  const Real bed_depth = 0.03;
  std::vector<Surrounding> out;
  out.push_back(ellipsoid_surrounding(
      "posterior wall", SurroundingKind::wall, Vec3(c.x(), c.y(), flat_side_z - kGap - bed_depth),
      Vec3(1.8 * half.x() + 0.04, 1.8 * half.y() + 0.04, bed_depth)));
  // The laparoscope works about 8 cm from the organ: the wall lies well beyond it, so its
  // lining shows dim under the scope's light.
  Surrounding wall = ellipsoid_surrounding("abdominal wall", SurroundingKind::wall,
                                           Vec3(c.x(), c.y(), flat_side_z),
                                           Vec3(half.x() + 0.14, half.y() + 0.14, 0.16));
  wall.inside_only = true;
  out.push_back(std::move(wall));
  out.push_back(ellipsoid_surrounding(
      "stomach", SurroundingKind::organ,
      Vec3(organ.min().x() - 0.55 * half.x(), c.y() + 0.3 * half.y(), flat_side_z + 0.2 * half.z()),
      Vec3(0.5 * half.x(), 0.7 * half.y(), 0.6 * half.z())));
  out.push_back(ellipsoid_surrounding(
      "omentum", SurroundingKind::fat,
      Vec3(c.x(), organ.max().y() + 0.25 * half.y(), flat_side_z - kGap - 0.35 * half.z()),
      Vec3(0.9 * half.x(), 0.4 * half.y(), 0.35 * half.z())));
  return out;
}

std::vector<Surrounding> knee_surroundings(std::vector<Surrounding> bones, const Box3& joint) {
  std::vector<Surrounding> out = std::move(bones);
  for (Surrounding& bone : out)
    bone.kind = SurroundingKind::bone;
  // The synovium lines the capsule a centimetre and a half beyond the joint's soft tissue; the
  // bones' shafts leave through it.
  Surrounding capsule =
      ellipsoid_surrounding("joint capsule", SurroundingKind::wall, joint.center(),
                            joint.sizes() / 2 + Vec3(0.012, 0.026, 0.016));
  capsule.inside_only = true;
  out.push_back(std::move(capsule));
  return out;
}

}  // namespace incise::sim::surgery
