#include "sim/mesh/cgal/implicit_shape.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace incise::sim {
namespace {

// Polynomial smooth minimum (see implicit_value in the header); k = 0 is the plain minimum.
Real smooth_min(Real a, Real b, Real k) {
  if (k <= 0) return std::min(a, b);
  const Real h = std::max(k - std::abs(a - b), Real(0)) / k;
  return std::min(a, b) - h * h * k / 4;
}

Real smooth_max(Real a, Real b, Real k) {
  return -smooth_min(-a, -b, k);
}

Real sphere_value(const Sphere& s, const Vec3& p) {
  return (p - s.centre).norm() - s.radius;
}

Real ellipsoid_value(const Ellipsoid& e, const Vec3& p) {
  const Vec3 d = p - e.centre;
  const Real k0 = d.cwiseQuotient(e.radii).norm();
  const Real k1 = d.cwiseQuotient(e.radii.cwiseProduct(e.radii)).norm();
  // At the centre the estimate is 0 / 0; the depth there is at least the smallest semi-axis.
  if (k1 == 0) return -e.radii.minCoeff();
  return k0 * (k0 - 1) / k1;
}

Real blend_value(const EllipsoidBlend& b, const Vec3& p) {
  Real f = ellipsoid_value(b.parts.front(), p);
  for (std::size_t i = 1; i < b.parts.size(); ++i) {
    f = smooth_min(f, ellipsoid_value(b.parts[i], p), b.blend_radius);
  }
  return f;
}

Real organ_value(const LobedOrgan& o, const Vec3& p) {
  return smooth_max(blend_value(o.lobes, p), o.flat_side_z - p.z(), o.lobes.blend_radius);
}

Box3 ellipsoid_box(const Ellipsoid& e) {
  return Box3(e.centre - e.radii, e.centre + e.radii);
}

Box3 blend_box(const EllipsoidBlend& b) {
  Box3 box;  // empty
  for (const Ellipsoid& e : b.parts)
    box.extend(ellipsoid_box(e));
  // The fillet lies where two parts are both within the blend radius.
  const Vec3 margin = Vec3::Constant(b.blend_radius);
  return Box3(box.min() - margin, box.max() + margin);
}

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("implicit shape: " + what);
}

void check_ellipsoid(const Ellipsoid& e, const std::string& name) {
  require(e.centre.allFinite(), name + " centre is not finite");
  require(e.radii.allFinite() && (e.radii.array() > 0).all(),
          name + " radii must be finite and > 0");
}

void check_blend(const EllipsoidBlend& b) {
  require(!b.parts.empty(), "an ellipsoid blend needs at least one part");
  require(std::isfinite(b.blend_radius) && b.blend_radius >= 0,
          "blend radius must be finite and >= 0");
  for (std::size_t i = 0; i < b.parts.size(); ++i) {
    check_ellipsoid(b.parts[i], "part " + std::to_string(i));
  }
}

}  // namespace

LobedOrgan liver_like_organ(const Vec3& centre, Real length) {
  const Real L = length;
  LobedOrgan organ;
  organ.lobes.parts = {
      {centre + L * Vec3(0.15, 0.0, 0.0), L * Vec3(0.35, 0.30, 0.17)},     // right lobe
      {centre + L * Vec3(-0.30, 0.05, 0.02), L * Vec3(0.28, 0.22, 0.11)},  // left lobe
      {centre + L * Vec3(0.0, -0.12, -0.05), L * Vec3(0.10, 0.08, 0.07)},  // caudate lobe
  };
  organ.lobes.blend_radius = L / 20;
  // The right lobe spans z in centre.z +- 0.17 L; cut a fifth of that height from below.
  organ.flat_side_z = centre.z() - 0.17 * L + 0.2 * (2 * 0.17 * L);
  return organ;
}

Real implicit_value(const ImplicitShape& shape, const Vec3& p) {
  struct Visitor {
    const Vec3& p;
    Real operator()(const Sphere& s) const { return sphere_value(s, p); }
    Real operator()(const Ellipsoid& e) const { return ellipsoid_value(e, p); }
    Real operator()(const EllipsoidBlend& b) const { return blend_value(b, p); }
    Real operator()(const LobedOrgan& o) const { return organ_value(o, p); }
  };
  return std::visit(Visitor{p}, shape);
}

Box3 implicit_extent(const ImplicitShape& shape) {
  struct Visitor {
    Box3 operator()(const Sphere& s) const {
      const Vec3 r = Vec3::Constant(s.radius);
      return Box3(s.centre - r, s.centre + r);
    }
    Box3 operator()(const Ellipsoid& e) const { return ellipsoid_box(e); }
    Box3 operator()(const EllipsoidBlend& b) const { return blend_box(b); }
    Box3 operator()(const LobedOrgan& o) const {
      Box3 box = blend_box(o.lobes);
      box.min().z() = std::max(box.min().z(), o.flat_side_z);
      return box;
    }
  };
  return std::visit(Visitor{}, shape);
}

void check_implicit_shape(const ImplicitShape& shape) {
  struct Visitor {
    void operator()(const Sphere& s) const {
      require(s.centre.allFinite(), "sphere centre is not finite");
      require(std::isfinite(s.radius) && s.radius > 0, "sphere radius must be finite and > 0");
    }
    void operator()(const Ellipsoid& e) const { check_ellipsoid(e, "ellipsoid"); }
    void operator()(const EllipsoidBlend& b) const { check_blend(b); }
    void operator()(const LobedOrgan& o) const {
      check_blend(o.lobes);
      require(std::isfinite(o.flat_side_z), "organ flat side is not finite");
      require(o.flat_side_z < blend_box(o.lobes).max().z(),
              "organ flat side z = " + std::to_string(o.flat_side_z) +
                  " lies above every lobe: nothing is left");
    }
  };
  std::visit(Visitor{}, shape);
}

}  // namespace incise::sim
