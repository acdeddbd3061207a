#include "sim/tools/blade_in_tissue.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "sim/tools/tool_checks.h"

namespace incise::sim::tools {
namespace {

// |cos| of the angle between the blade and a face's normal at or below which the face is
// parallel to the blade (a crack the blade lies in; exactly 0 at rest, rounding otherwise).
constexpr Real kParallel = 1e-9;
// Barycentric slack: a line through an edge is taken by the faces on both sides (and then counted
// once by the walk), never by neither.
constexpr Real kEdgeSlack = 1e-9;
// Crossings closer than this fraction of the blade's length are at one place; the query capsule's
// radius is a larger fraction, so that it finds every face the slack admits.
constexpr Real kSamePlace = 1e-9;
constexpr Real kQueryRadius = 1e-7;

// Where the line tip + s u, s in [s0, s1], crosses the triangle (a, b, c) (outward normal
// (b - a) x (c - a)), and whether it goes in there.
bool crossing(const Vec3& tip, const Vec3& u, Real s0, Real s1, const Vec3& a, const Vec3& b,
              const Vec3& c, Real& s, bool& entering) {
  const Vec3 n = (b - a).cross(c - a);
  const Real area2 = n.squaredNorm();
  const Real along = n.dot(u);
  if (!(std::abs(along) > kParallel * std::sqrt(area2))) return false;  // parallel or degenerate
  s = n.dot(a - tip) / along;
  if (!(s >= s0 && s <= s1)) return false;
  const Vec3 q = tip + s * u;
  // (b - a) x (q - a) . n is q's barycentric weight of c times |n|^2, and so on.
  const Real slack = -kEdgeSlack * area2;
  if ((b - a).cross(q - a).dot(n) < slack || (c - b).cross(q - b).dot(n) < slack ||
      (a - c).cross(q - c).dot(n) < slack) {
    return false;
  }
  entering = along < 0;
  return true;
}

// The crossings with s in [s0, s1] into found.crossings (cleared first), in tree order.
void collect(const collide::SurfaceBvh& bvh, const Points& x, const Vec3& tip, const Vec3& u,
             Real s0, Real s1, Real radius, BladeInTissue& found) {
  found.crossings.clear();
  bvh.overlapping_triangles(x, collide::Capsule{tip + s0 * u, tip + s1 * u, radius}, found.slots);
  for (const int slot : found.slots) {
    const Vec3i& t = bvh.triangle(slot);
    BladeCrossing c;
    c.face = slot;
    if (crossing(tip, u, s0, s1, row3(x, t[0]), row3(x, t[1]), row3(x, t[2]), c.distance,
                 c.entering)) {
      found.crossings.push_back(c);
    }
  }
}

}  // namespace

void blade_in_tissue(const collide::SurfaceBvh& bvh, const Points& x, const Vec3& tip,
                     const Vec3& direction, Real length, Real reach, Real bridge,
                     BladeInTissue& found) {
  checks::check_vector(tip, "blade_in_tissue", "the tip");
  checks::check_vector(direction, "blade_in_tissue", "the direction");
  if (!(std::abs(direction.norm() - 1) <= 1e-6)) {
    throw std::invalid_argument("blade_in_tissue: the direction must be a unit vector");
  }
  if (!(length > 0 && std::isfinite(length))) {
    throw std::invalid_argument("blade_in_tissue: the blade's length must be > 0");
  }
  if (!(reach >= 0 && std::isfinite(reach))) {
    throw std::invalid_argument("blade_in_tissue: the reach must be >= 0");
  }
  if (!(bridge >= 0 && std::isfinite(bridge))) {
    throw std::invalid_argument("blade_in_tissue: the bridge must be >= 0");
  }
  found.depth = 0;
  found.stretches.clear();
  const Vec3 u = -direction;
  const Real radius = kQueryRadius * length;
  const Real same = kSamePlace * length;
  std::vector<BladeCrossing>& crossings = found.crossings;
  collect(bvh, x, tip, u, 0, length, radius, found);
  if (crossings.empty()) {
    // Wholly in or wholly out: the first crossing further back says which (at one place, a way
    // out wins, as below).
    for (Real s0 = length; s0 < length + reach; s0 += length) {
      collect(bvh, x, tip, u, s0, std::min(s0 + length, length + reach), radius, found);
      if (crossings.empty()) continue;
      Real first = crossings.front().distance;
      for (const BladeCrossing& c : crossings)
        first = std::min(first, c.distance);
      const auto out = std::find_if(
          crossings.begin(), crossings.end(),
          [&](const BladeCrossing& c) { return !c.entering && c.distance - first <= same; });
      if (out != crossings.end()) {
        found.stretches.push_back({0, length, out->face});
        found.depth = length;
      }
      return;
    }
    return;
  }
  std::sort(crossings.begin(), crossings.end(),
            [](const BladeCrossing& a, const BladeCrossing& b) { return a.distance < b.distance; });
  // Ways out first among crossings at one place.
  for (std::size_t k = 1; k < crossings.size(); ++k) {
    for (std::size_t j = k; j > 0; --j) {
      BladeCrossing& before = crossings[j - 1];
      BladeCrossing& after = crossings[j];
      if (!(before.entering && !after.entering && after.distance - before.distance <= same)) break;
      std::swap(before, after);
    }
  }
  bool inside = !crossings.front().entering;
  Real from = 0;
  int face = -1;
  for (const BladeCrossing& c : crossings) {
    if (inside && !c.entering) {
      found.stretches.push_back({from, c.distance, face >= 0 ? face : c.face});
      inside = false;
    } else if (!inside && c.entering) {
      inside = true;
      if (!found.stretches.empty() &&
          c.distance - found.stretches.back().to <= std::max(same, bridge)) {
        // Back in where it came out, or nearly: a crack, inside one stretch.
        from = found.stretches.back().from;
        face = found.stretches.back().face;
        found.stretches.pop_back();
      } else {
        from = c.distance;
        face = c.face;
      }
    }
  }
  if (inside) found.stretches.push_back({from, length, face});
  Real depth = 0;
  for (const BladeStretch& s : found.stretches)
    depth += s.to - s.from;
  found.depth = std::min(depth, length);
}

}  // namespace incise::sim::tools
