#include "sim/plan/penetration_planner.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace incise::sim::plan {
namespace {

// The cell of a uniform grid of `size` that holds p, and its key in a hash map: 21 bits a
// coordinate, so cells of a millimetre or more cover +-1 km.
Vec3i cell_of(const Vec3& p, Real size) {
  return Vec3i(static_cast<int>(std::floor(p.x() / size)),
               static_cast<int>(std::floor(p.y() / size)),
               static_cast<int>(std::floor(p.z() / size)));
}

std::int64_t cell_key(const Vec3i& c) {
  const auto part = [](int v) { return static_cast<std::int64_t>(v & 0x1FFFFF); };
  return part(c.x()) | (part(c.y()) << 21) | (part(c.z()) << 42);
}

// The obstacles' points in a uniform grid of cells as large as the cost's sphere: a query visits
// the 27 cells around it. Built once per plan.
class PointGrid {
 public:
  PointGrid(const std::vector<Obstacle>& obstacles, Real cell) : cell_(cell) {
    for (int o = 0; o < static_cast<int>(obstacles.size()); ++o) {
      const auto& points = obstacles[o].points;
      for (int i = 0; i < points.rows(); ++i)
        cells_[cell_key(cell_of(row3(points, i), cell_))].push_back({o, i});
    }
  }

  // Calls visit(obstacle, point) for every point within the 27 cells around p.
  template <class Visit>
  void around(const Vec3& p, Visit&& visit) const {
    const Vec3i c = cell_of(p, cell_);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(cell_key(c + Vec3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const auto& [o, i] : it->second)
            visit(o, i);
        }
  }

 private:
  Real cell_;
  std::unordered_map<std::int64_t, std::vector<std::pair<int, int>>> cells_;
};

class Problem {
 public:
  Problem(const Vec3& from, const Vec3& to, const std::vector<Obstacle>& obstacles,
          const PlanOptions& options)
      : from_(from),
        chord_(to - from),
        obstacles_(obstacles),
        options_(options),
        radius_(options.probe_radius * options.inflation),
        grid_(obstacles, radius_),
        terms_(options.degree - 1) {
    for (const auto& o : obstacles)
      depth_.push_back(o.depth.size() == o.points.rows() ? o.depth : surface_depth(o.points));
    for (int i = 0; i < options.samples; ++i) {
      // Midpoints: the ends are fixed and never counted twice.
      const Real s = (i + 0.5) / options.samples;
      s_.push_back(s);
    }
  }

  int unknowns() const { return 3 * terms_; }

  Vec3 position(const VecX& c, Real s) const {
    Vec3 bend = Vec3::Zero();
    Real power = 1;
    for (int k = 0; k < terms_; ++k, power *= s)
      bend += power * c.segment<3>(3 * k);
    return from_ + chord_ * s + s * (1 - s) * bend;
  }

  // The cost at c, and its gradient in `gradient` when not null.
  Real cost(const VecX& c, VecX* gradient) const {
    if (gradient) gradient->setZero(unknowns());
    Real total = 0;
    const Real r = radius_;
    for (const Real s : s_) {
      const Vec3 p = position(c, s);
      Vec3 pull = Vec3::Zero();  // d(penetration cost)/dp
      grid_.around(p, [&](int o, int i) {
        const Vec3 away = p - row3(obstacles_[o].points, i);
        const Real d = away.norm();
        if (d >= r) return;
        const Real depth = depth_[o][i] + r - d;
        const Real k = obstacles_[o].stiffness;
        total += k * depth * depth;
        // At d = 0 the direction is undefined; such a point pulls nowhere.
        if (d > 0) pull += -2 * k * depth * away / d;
      });
      // Bending: p'(s) - (b - a) = d/ds [s (1 - s) sum c_k s^k].
      Vec3 slope = Vec3::Zero();
      std::vector<Real> dslope(terms_);
      for (int k = 0; k < terms_; ++k) {
        dslope[k] = (k + 1) * std::pow(s, k) - (k + 2) * std::pow(s, k + 1);
        slope += dslope[k] * c.segment<3>(3 * k);
      }
      total += options_.bend_weight * slope.squaredNorm();
      if (gradient) {
        Real power = 1;
        for (int k = 0; k < terms_; ++k, power *= s) {
          gradient->segment<3>(3 * k) +=
              s * (1 - s) * power * pull + options_.bend_weight * 2 * dslope[k] * slope;
        }
      }
    }
    const Real n = static_cast<Real>(s_.size());
    if (gradient) *gradient /= n;
    return total / n;
  }

  // How deep the probe itself (not inflated) enters: the deepest point inside its sphere, along
  // the path sampled densely, per obstacle.
  std::vector<std::pair<Real, Real>> penetration(const VecX& c) const {
    std::vector<std::pair<Real, Real>> deepest(obstacles_.size(), {0.0, 0.0});  // depth, s
    const int n = 4 * options_.samples;
    for (int j = 0; j <= n; ++j) {
      const Real s = static_cast<Real>(j) / n;
      const Vec3 p = position(c, s);
      grid_.around(p, [&](int o, int i) {
        const Real d = (p - row3(obstacles_[o].points, i)).norm();
        if (d >= options_.probe_radius) return;
        const Real depth = depth_[o][i] + options_.probe_radius - d;
        if (depth > deepest[o].first) deepest[o] = {depth, s};
      });
    }
    return deepest;
  }

 private:
  Vec3 from_;
  Vec3 chord_;
  const std::vector<Obstacle>& obstacles_;
  PlanOptions options_;
  Real radius_;
  PointGrid grid_;
  int terms_;
  std::vector<VecX> depth_;  // per obstacle, per point
  std::vector<Real> s_;
};

struct Descent {
  VecX c;
  Real cost = 0;
  std::vector<Real> history;
  int iterations = 0;
  int evaluations = 0;
};

// Gradient descent from c0 with a backtracking line search: a step is taken only if it lowers the
// cost (Armijo's condition); the step length grows after a success and halves after a failure.
Descent descend(const Problem& problem, VecX c0, const PlanOptions& options, Real length_scale) {
  Descent out;
  out.c = std::move(c0);
  VecX gradient;
  out.cost = problem.cost(out.c, &gradient);
  ++out.evaluations;
  out.history.push_back(out.cost);
  // The first trial step moves the path by a tenth of the chord.
  Real step = 0.1 * length_scale / std::max<Real>(gradient.norm(), 1e-300);
  for (int it = 0; it < options.max_iterations; ++it) {
    const Real slope = gradient.squaredNorm();
    if (slope == 0 || !std::isfinite(slope)) break;
    bool accepted = false;
    for (int tries = 0; tries < 40; ++tries) {
      const VecX trial = out.c - step * gradient;
      VecX trial_gradient;
      const Real trial_cost = problem.cost(trial, &trial_gradient);
      ++out.evaluations;
      if (std::isfinite(trial_cost) && trial_cost <= out.cost - 1e-4 * step * slope) {
        out.c = trial;
        out.cost = trial_cost;
        gradient = trial_gradient;
        step *= 2;
        accepted = true;
        break;
      }
      step /= 2;
    }
    if (!accepted) break;
    ++out.iterations;
    out.history.push_back(out.cost);
    if (out.history.size() >= 2 &&
        out.history[out.history.size() - 2] - out.cost <= 1e-9 * out.history.front()) {
      break;  // no longer moving
    }
  }
  return out;
}

void check(const Vec3& from, const Vec3& to, const PlanOptions& o) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (!from.allFinite() || !to.allFinite()) fail("the start and the goal must be finite");
  if ((to - from).norm() <= 0) fail("the start and the goal are the same point");
  if (o.degree < 2 || o.degree > 7) fail("degree must be 2 to 7");
  if (!(o.probe_radius > 0) || !std::isfinite(o.probe_radius)) fail("probe_radius must be > 0");
  if (!(o.inflation >= 1) || !std::isfinite(o.inflation)) fail("inflation must be >= 1");
  if (o.samples < 4 || o.samples > 4096) fail("samples must be 4 to 4096");
  if (o.max_iterations < 0 || o.max_iterations > 100000) fail("max_iterations must be 0 to 100000");
  if (!(o.bend_weight >= 0) || !std::isfinite(o.bend_weight)) fail("bend_weight must be >= 0");
  if (!(o.penetration_bound >= 0)) fail("penetration_bound must be >= 0");
}

}  // namespace

VecX surface_depth(const Points& points) {
  const int n = static_cast<int>(points.rows());
  VecX depth = VecX::Zero(n);
  if (n < 8) return depth;  // too few to have an inside
  // The spacing: the median distance to the nearest other point, found on a grid whose cells hold
  // a few points each.
  const Box3 box(points.colwise().minCoeff().transpose(), points.colwise().maxCoeff().transpose());
  const Real guess = std::max<Real>(std::cbrt(box.volume() / n), box.diagonal().norm() / n);
  std::vector<Obstacle> one(1);
  one[0].points = points;
  const PointGrid near_grid(one, 2 * guess);
  std::vector<Real> nearest(n);
  for (int i = 0; i < n; ++i) {
    Real best = std::numeric_limits<Real>::infinity();
    near_grid.around(row3(points, i), [&](int, int j) {
      if (j != i) best = std::min(best, (row3(points, j) - row3(points, i)).squaredNorm());
    });
    nearest[i] = std::sqrt(best);
  }
  std::nth_element(nearest.begin(), nearest.begin() + n / 2, nearest.end());
  const Real spacing = std::isfinite(nearest[n / 2]) ? nearest[n / 2] : guess;
  // Boundary points: their neighbours within 2.5 spacings are lopsided around them (an inside
  // point's neighbours surround it, and their centroid is the point itself).
  const Real reach = 2.5 * spacing;
  const PointGrid grid(one, reach);
  std::vector<int> boundary;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = row3(points, i);
    Vec3 sum = Vec3::Zero();
    int count = 0;
    grid.around(p, [&](int, int j) {
      const Vec3 q = row3(points, j);
      if ((q - p).norm() > reach) return;
      sum += q;
      ++count;
    });
    if (count < 7 || (sum / count - p).norm() > 0.25 * spacing) boundary.push_back(i);
  }
  if (boundary.empty()) return depth;
  // The nearest boundary point, searched on a grid in growing shells of cells: a shell at ring
  // distance k cannot hold anything nearer than (k - 1) cells.
  const Real cell = 2 * spacing;
  std::unordered_map<std::int64_t, std::vector<int>> cells;
  for (const int b : boundary)
    cells[cell_key(cell_of(row3(points, b), cell))].push_back(b);
  const int max_ring = static_cast<int>(std::ceil(box.diagonal().norm() / cell)) + 1;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = row3(points, i);
    const Vec3i c = cell_of(p, cell);
    Real best = std::numeric_limits<Real>::infinity();
    for (int ring = 0; ring <= max_ring; ++ring) {
      if (std::sqrt(best) <= (ring - 1) * cell) break;
      for (int dx = -ring; dx <= ring; ++dx)
        for (int dy = -ring; dy <= ring; ++dy)
          for (int dz = -ring; dz <= ring; ++dz) {
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != ring) continue;
            const auto it = cells.find(cell_key(c + Vec3i(dx, dy, dz)));
            if (it == cells.end()) continue;
            for (const int b : it->second)
              best = std::min(best, (row3(points, b) - p).squaredNorm());
          }
    }
    depth[i] = std::sqrt(best);
  }
  return depth;
}

Points volume_points(const Points& nodes, const Tets& tets, Real spacing) {
  if (!(spacing > 0)) throw std::invalid_argument("spacing must be > 0");
  std::unordered_map<std::int64_t, Vec3> found;  // by lattice cell: a point on a shared face once
  for (int t = 0; t < tets.rows(); ++t) {
    const Vec3 a = row3(nodes, tets(t, 0));
    Mat3 edges;
    edges << row3(nodes, tets(t, 1)) - a, row3(nodes, tets(t, 2)) - a, row3(nodes, tets(t, 3)) - a;
    if (std::abs(edges.determinant()) < 1e-30) continue;  // a flat tet holds no volume
    const Mat3 to_barycentric = edges.inverse();
    Box3 box;
    for (int k = 0; k < 4; ++k)
      box.extend(row3(nodes, tets(t, k)));
    const Vec3i lo = (box.min() / spacing).array().ceil().cast<int>();
    const Vec3i hi = (box.max() / spacing).array().floor().cast<int>();
    for (int i = lo.x(); i <= hi.x(); ++i)
      for (int j = lo.y(); j <= hi.y(); ++j)
        for (int k = lo.z(); k <= hi.z(); ++k) {
          const Vec3 q(i * spacing, j * spacing, k * spacing);
          const Vec3 b = to_barycentric * (q - a);
          if (b.minCoeff() < -1e-12 || b.sum() > 1 + 1e-12) continue;
          found.emplace(cell_key(Vec3i(i, j, k)), q);
        }
  }
  Points out(static_cast<Eigen::Index>(found.size()), 3);
  // In lattice order, not the map's: the same mesh gives the same points in the same order.
  std::vector<std::pair<std::int64_t, Vec3>> sorted(found.begin(), found.end());
  std::sort(sorted.begin(), sorted.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  for (std::size_t r = 0; r < sorted.size(); ++r)
    out.row(static_cast<Eigen::Index>(r)) = sorted[r].second.transpose();
  return out;
}

Vec3 PlannedPath::at(Real s) const {
  Vec3 bent = Vec3::Zero();
  Real power = 1;
  for (const auto& c : bend) {
    bent += power * c;
    power *= s;
  }
  return from + (to - from) * s + s * (1 - s) * bent;
}

std::vector<Vec3> PlannedPath::polyline(int n) const {
  std::vector<Vec3> out;
  n = std::max(n, 2);
  for (int i = 0; i < n; ++i)
    out.push_back(at(static_cast<Real>(i) / (n - 1)));
  return out;
}

PlannedPath plan_path(const Vec3& from, const Vec3& to, const std::vector<Obstacle>& obstacles,
                      const PlanOptions& options) {
  check(from, to, options);
  for (const auto& o : obstacles) {
    if (o.depth.size() != 0 && o.depth.size() != o.points.rows()) {
      throw std::invalid_argument("obstacle \"" + o.name + "\": one depth a point, or none");
    }
    if (!(o.stiffness >= 0) || !std::isfinite(o.stiffness) || !o.points.allFinite()) {
      throw std::invalid_argument("obstacle \"" + o.name +
                                  "\": stiffness must be >= 0 and its points finite");
    }
  }
  const Problem problem(from, to, obstacles, options);
  const Vec3 chord = to - from;
  const Real length = chord.norm();

  // The starts: the straight line, and bends to four sides of it whose largest offset (at
  // s = 1/2) is an eighth of the chord.
  Vec3 u = chord.unitOrthogonal();
  Vec3 v = chord.normalized().cross(u);
  std::vector<VecX> starts(1, VecX::Zero(problem.unknowns()));
  for (const Vec3& side : {u, Vec3(-u), v, Vec3(-v)}) {
    VecX c = VecX::Zero(problem.unknowns());
    c.segment<3>(0) = 0.5 * length * side;
    starts.push_back(c);
  }

  PlannedPath out;
  out.from = from;
  out.to = to;
  out.straight_cost = problem.cost(starts.front(), nullptr);
  Descent best;
  bool first = true;
  for (const auto& c0 : starts) {
    auto d = descend(problem, c0, options, length);
    out.iterations += d.iterations;
    out.evaluations += d.evaluations;
    if (first || d.cost < best.cost) {
      best = std::move(d);
      first = false;
    }
    // Nothing in the way of the straight line: it is the answer (no bend is cheaper).
    if (out.straight_cost == 0) break;
  }
  out.cost = best.cost;
  out.cost_history = best.history;
  for (int k = 0; k + 1 < options.degree; ++k)
    out.bend.push_back(best.c.segment<3>(3 * k));

  const auto deepest = problem.penetration(best.c);
  for (std::size_t o = 0; o < obstacles.size(); ++o) {
    const auto [depth, s] = deepest[o];
    if (depth > out.max_penetration) {
      out.max_penetration = depth;
      out.deepest_obstacle = obstacles[o].name;
    }
    if (!obstacles[o].protect || depth <= out.max_protected_penetration) continue;
    out.max_protected_penetration = depth;
    if (depth > options.penetration_bound) {
      const Vec3 at = out.at(s);
      std::ostringstream why;
      why.precision(3);
      why << "no path found keeps the probe within " << options.penetration_bound * 1000
          << " mm of \"" << obstacles[o].name << "\": the best enters it " << depth * 1000
          << " mm at (" << at.x() << ", " << at.y() << ", " << at.z() << ")";
      out.within_bound = false;
      out.problem = why.str();
    }
  }
  return out;
}

}  // namespace incise::sim::plan
