#include "sim/remesh/adaptation_regions.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

#include "sim/mesh/tet_adjacency.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::remesh {
namespace {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("AdaptationCriteria: " + what);
}

// A finite level pair with 0 <= off <= on.
void check_band(const char* name, Real on, Real off) {
  require(std::isfinite(on) && std::isfinite(off) && off >= 0 && off <= on,
          std::string(name) + " needs 0 <= off <= on, got on " + std::to_string(on) + ", off " +
              std::to_string(off));
}

Real point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const Real length2 = ab.squaredNorm();
  const Real t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, Real(0), Real(1)) : Real(0);
  return (p - a - t * ab).norm();
}

// If p's projection onto the triangle's plane falls inside the triangle, the distance is the
// plane's; otherwise the nearest point is on the triangle's border.
Real point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const Real n2 = n.squaredNorm();
  if (n2 > 0) {
    const Real height = n.dot(p - a);
    const Vec3 q = p - n * (height / n2);
    if (n.dot((b - a).cross(q - a)) >= 0 && n.dot((c - b).cross(q - b)) >= 0 &&
        n.dot((a - c).cross(q - c)) >= 0) {
      return std::abs(height) / std::sqrt(n2);
    }
  }
  return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, c),
                   point_segment_distance(p, c, a)});
}

// Distance from p to the axis-aligned box spanned by the points (0 inside): a lower bound on
// the distance to their convex hull, to skip far tools cheaply.
Real point_box_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 lo = a.cwiseMin(b).cwiseMin(c).cwiseMin(d);
  const Vec3 hi = a.cwiseMax(b).cwiseMax(c).cwiseMax(d);
  return (p - p.cwiseMax(lo).cwiseMin(hi)).norm();
}

// The signed angle [rad] from face A's outward normal to face B's, about their shared edge
// directed as in A's cyclic order; 0 where the surface is flat; NaN if a face or the edge is
// degenerate.
Real signed_dihedral(const Vec3& from, const Vec3& to, const Vec3& normal_a, const Vec3& normal_b) {
  const Vec3 edge = to - from;
  const Real edge_length = edge.norm();
  if (edge_length == 0 || normal_a.squaredNorm() == 0 || normal_b.squaredNorm() == 0) {
    return std::numeric_limits<Real>::quiet_NaN();
  }
  return std::atan2(edge.dot(normal_a.cross(normal_b)) / edge_length, normal_a.dot(normal_b));
}

Vec3 face_normal(const Points& points, const Tets& tets, int tet, int face) {
  const Vec3 a = row3(points, tets(tet, kTetFaces[face][0]));
  const Vec3 b = row3(points, tets(tet, kTetFaces[face][1]));
  const Vec3 c = row3(points, tets(tet, kTetFaces[face][2]));
  return (b - a).cross(c - a);
}

}  // namespace

Real green_strain_norm(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& xa,
                       const Vec3& xb, const Vec3& xc, const Vec3& xd) {
  Mat3 dm;
  dm << b - a, c - a, d - a;
  const Real det = dm.determinant();
  if (!(det > 0)) {
    throw std::invalid_argument(
        "green_strain_norm: rest tet is flat or inverted (6 V = " + std::to_string(det) + ")");
  }
  Mat3 ds;
  ds << xb - xa, xc - xa, xd - xa;
  const Mat3 f = ds * dm.inverse();
  return ((f.transpose() * f - Mat3::Identity()) / 2).norm();
}

Real point_tet_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Real volume = signed_volume(a, b, c, d);
  if (volume != 0) {
    // Inside if p is on the tet's side of every face: the four sub-tets with p in place of one
    // vertex have the tet's sign (or are flat).
    const Real s[4] = {signed_volume(p, b, c, d), signed_volume(a, p, c, d),
                       signed_volume(a, b, p, d), signed_volume(a, b, c, p)};
    bool inside = true;
    for (Real si : s)
      inside = inside && si * volume >= 0;
    if (inside) return 0;
  }
  return std::min({point_triangle_distance(p, b, c, d), point_triangle_distance(p, a, c, d),
                   point_triangle_distance(p, a, b, d), point_triangle_distance(p, a, b, c)});
}

AdaptationRegions::AdaptationRegions(const AdaptationCriteria& criteria) : criteria_(criteria) {
  const AdaptationCriteria& c = criteria;
  require(c.fine_size > 0 && std::isfinite(c.fine_size),
          "fine_size must be > 0 and finite, got " + std::to_string(c.fine_size));
  require(c.coarse_size >= c.fine_size, "coarse_size must be >= fine_size");
  require(c.grading >= 0 && std::isfinite(c.grading), "grading must be >= 0 and finite");
  require(c.keep_margin >= 0 && std::isfinite(c.keep_margin),
          "keep_margin must be >= 0 and finite");
  require(c.merge_distance >= 0 && std::isfinite(c.merge_distance),
          "merge_distance must be >= 0 and finite");
  if (c.contact) {
    require(c.contact_radius >= 0 && std::isfinite(c.contact_release) &&
                c.contact_release >= c.contact_radius,
            "contact needs 0 <= contact_radius <= contact_release (finite)");
  }
  if (c.strain) check_band("strain", c.strain_on, c.strain_off);
  if (c.curvature) check_band("bend", c.bend_on, c.bend_off);
}

void AdaptationRegions::update(const Points& rest, const Points& x, const Tets& tets,
                               const Tets& neighbors, std::span<const char> alive,
                               std::span<const Vec3> tools) {
  const int num_tets = static_cast<int>(tets.rows());
  const int num_vertices = static_cast<int>(rest.rows());
  if (x.rows() != rest.rows()) {
    throw std::invalid_argument("AdaptationRegions::update: x has " + std::to_string(x.rows()) +
                                " rows, rest has " + std::to_string(rest.rows()));
  }
  if (!alive.empty() && static_cast<int>(alive.size()) != num_tets) {
    throw std::invalid_argument("AdaptationRegions::update: alive has " +
                                std::to_string(alive.size()) + " flags for " +
                                std::to_string(num_tets) + " tets");
  }
  if (criteria_.curvature && neighbors.rows() != tets.rows()) {
    throw std::invalid_argument("AdaptationRegions::update: neighbors has " +
                                std::to_string(neighbors.rows()) + " rows for " +
                                std::to_string(num_tets) + " tets");
  }
  const auto is_alive = [&](int t) { return alive.empty() || alive[t] != 0; };

  marks_.assign(num_tets, TetMark::kCold);
  tool_distance_.assign(num_tets, kInfinity);
  strain_.assign(num_tets, 0);
  bend_.assign(num_tets, 0);

  for (int t = 0; t < num_tets; ++t) {
    if (!is_alive(t)) continue;
    for (int k = 0; k < 4; ++k) {
      if (tets(t, k) < 0 || tets(t, k) >= num_vertices) {
        throw std::invalid_argument("AdaptationRegions::update: tet " + std::to_string(t) +
                                    " has vertex " + std::to_string(tets(t, k)) + " outside [0, " +
                                    std::to_string(num_vertices) + ")");
      }
    }
    const Vec3 xa = row3(x, tets(t, 0)), xb = row3(x, tets(t, 1));
    const Vec3 xc = row3(x, tets(t, 2)), xd = row3(x, tets(t, 3));
    if (criteria_.contact) {
      for (const Vec3& tool : tools) {
        if (point_box_distance(tool, xa, xb, xc, xd) > criteria_.contact_release) continue;
        tool_distance_[t] = std::min(tool_distance_[t], point_tet_distance(tool, xa, xb, xc, xd));
      }
    }
    if (criteria_.strain) {
      strain_[t] =
          green_strain_norm(row3(rest, tets(t, 0)), row3(rest, tets(t, 1)), row3(rest, tets(t, 2)),
                            row3(rest, tets(t, 3)), xa, xb, xc, xd);
    }
  }
  if (criteria_.curvature) measure_bend(rest, x, tets, neighbors, alive);

  const AdaptationCriteria& c = criteria_;
  for (int t = 0; t < num_tets; ++t) {
    if (!is_alive(t)) continue;
    const bool hot = (c.contact && tool_distance_[t] <= c.contact_radius) ||
                     (c.strain && strain_[t] >= c.strain_on) ||
                     (c.curvature && bend_[t] >= c.bend_on);
    const bool warm = (c.contact && tool_distance_[t] <= c.contact_release) ||
                      (c.strain && strain_[t] >= c.strain_off) ||
                      (c.curvature && bend_[t] >= c.bend_off);
    marks_[t] = hot ? TetMark::kHot : warm ? TetMark::kWarm : TetMark::kCold;
  }

  const auto centroid = [&](int t) {
    return Vec3((row3(rest, tets(t, 0)) + row3(rest, tets(t, 1)) + row3(rest, tets(t, 2)) +
                 row3(rest, tets(t, 3))) /
                4);
  };
  // 1. Hysteresis: a ball survives while a tet in it is past an off level.
  next_balls_.clear();
  for (const RegionBall& ball : balls_) {
    for (int t = 0; t < num_tets; ++t) {
      if (marks_[t] == TetMark::kCold) continue;
      if ((centroid(t) - ball.center).squaredNorm() <= ball.radius * ball.radius) {
        next_balls_.push_back(ball);
        break;
      }
    }
  }
  // 2. Hot tets not yet covered join or start a ball.
  for (int t = 0; t < num_tets; ++t) {
    if (marks_[t] != TetMark::kHot) continue;
    const Vec3 center = centroid(t);
    Real radius = 0;
    for (int k = 0; k < 4; ++k)
      radius = std::max(radius, (row3(rest, tets(t, k)) - center).norm());
    RegionBall* nearest = nullptr;
    Real nearest_distance = kInfinity;
    bool covered = false;
    for (RegionBall& ball : next_balls_) {
      const Real distance = (center - ball.center).norm();
      if (distance + radius <= ball.radius) {
        covered = true;
        break;
      }
      if (distance <= c.merge_distance && distance < nearest_distance) {
        nearest = &ball;
        nearest_distance = distance;
      }
    }
    if (covered) continue;
    if (nearest != nullptr) {
      nearest->radius = std::max(nearest->radius, nearest_distance + radius);
    } else {
      next_balls_.push_back({center, radius});
    }
  }
  balls_.swap(next_balls_);
}

void AdaptationRegions::measure_bend(const Points& rest, const Points& x, const Tets& tets,
                                     const Tets& neighbors, std::span<const char> alive) {
  edges_.clear();
  for (int t = 0; t < tets.rows(); ++t) {
    if (!alive.empty() && alive[t] == 0) continue;
    for (int k = 0; k < 4; ++k) {
      if (neighbors(t, k) >= 0) continue;
      for (int i = 0; i < 3; ++i) {
        const int from = tets(t, kTetFaces[k][i]);
        const int to = tets(t, kTetFaces[k][(i + 1) % 3]);
        edges_.push_back({std::min(from, to), std::max(from, to), from, t, k});
      }
    }
  }
  std::sort(edges_.begin(), edges_.end(), [](const BoundaryEdge& p, const BoundaryEdge& q) {
    return p.lo != q.lo ? p.lo < q.lo : p.hi < q.hi;
  });
  // A manifold surface has exactly two faces at each edge; an edge where more meet (tets touching
  // along an edge only) has no single bend and is skipped.
  for (size_t i = 0; i < edges_.size();) {
    size_t j = i + 1;
    while (j < edges_.size() && edges_[j].lo == edges_[i].lo && edges_[j].hi == edges_[i].hi)
      ++j;
    if (j - i == 2) {
      const BoundaryEdge& a = edges_[i];
      const BoundaryEdge& b = edges_[i + 1];
      const int to = a.from == a.lo ? a.hi : a.lo;
      const Real at_rest = signed_dihedral(row3(rest, a.from), row3(rest, to),
                                           face_normal(rest, tets, a.tet, a.face),
                                           face_normal(rest, tets, b.tet, b.face));
      const Real deformed =
          signed_dihedral(row3(x, a.from), row3(x, to), face_normal(x, tets, a.tet, a.face),
                          face_normal(x, tets, b.tet, b.face));
      if (std::isfinite(at_rest) && std::isfinite(deformed)) {
        Real change = std::abs(deformed - at_rest);  // in [0, 2 pi)
        if (change > std::numbers::pi) change = 2 * std::numbers::pi - change;
        bend_[a.tet] = std::max(bend_[a.tet], change);
        bend_[b.tet] = std::max(bend_[b.tet], change);
      }
    }
    i = j;
  }
}

SizeField AdaptationRegions::field(Real margin) const {
  return [balls = balls_, margin, fine = criteria_.fine_size, coarse = criteria_.coarse_size,
          grading = criteria_.grading](const Vec3& p) {
    Real distance = kInfinity;
    for (const RegionBall& ball : balls)
      distance = std::min(distance, (p - ball.center).norm() - ball.radius - margin);
    if (distance <= 0) return fine;
    if (grading > 0 && fine + grading * distance < coarse) return fine + grading * distance;
    return kInfinity;
  };
}

std::optional<RegionHint> AdaptationRegions::refine_hint() const {
  if (balls_.empty()) return std::nullopt;
  // The band: fine + grading d < coarse, i.e. d < (coarse - fine) / grading.
  const Real band = criteria_.grading > 0 && std::isfinite(criteria_.coarse_size)
                        ? (criteria_.coarse_size - criteria_.fine_size) / criteria_.grading
                        : (criteria_.grading > 0 ? kInfinity : 0);
  if (!std::isfinite(band)) return std::nullopt;  // the field is finite everywhere
  Eigen::AlignedBox<Real, 3> box;
  for (const RegionBall& ball : balls_) {
    box.extend(ball.center - Vec3::Constant(ball.radius + band));
    box.extend(ball.center + Vec3::Constant(ball.radius + band));
  }
  return region_hint_of(box.center(), 0.5 * box.diagonal().norm());
}

SizeField AdaptationRegions::refine_field() const {
  return field(0);
}

SizeField AdaptationRegions::keep_field() const {
  return field(criteria_.keep_margin);
}

}  // namespace incise::sim::remesh
