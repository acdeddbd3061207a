// bench_planning: seed 004's planning experiment. 3 to 10 irregular obstacles of about 1,300
// points each, strung along a 10 cm path alternately above and below it, stiffnesses 1 to 10;
// the minimum-penetration path of degree 3 and of degree 5 (sim/plan/penetration_planner.h).
// Prints per case the cost of the straight line and of the path, the deepest penetration of the
// 2 mm probe, the descent's steps and cost evaluations, and the time (median of 5 runs).
// Usage: bench_planning
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "bench/median.h"
#include "sim/plan/penetration_planner.h"

using namespace incise::sim;
using namespace incise::sim::plan;

namespace {

// An irregular blob: a lattice ellipsoid whose radius wobbles with direction, about `count`
// points. Deterministic for a given seed.
Points blob(const Vec3& centre, Real size, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<Real> unit(-1, 1);
  const Vec3 axes(size * (1 + 0.3 * unit(random)), size * (1 + 0.3 * unit(random)),
                  size * (1 + 0.3 * unit(random)));
  const Vec3 wobble(unit(random), unit(random), unit(random));
  // Lattice spacing for about `count` points inside the ellipsoid (volume 4/3 pi abc).
  const Real h = std::cbrt(4.0 / 3.0 * M_PI * axes.prod() / count);
  std::vector<Vec3> inside;
  const int n = static_cast<int>(std::ceil(axes.maxCoeff() * 1.3 / h));
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Vec3 q(i * h, j * h, k * h);
        const Vec3 scaled = q.cwiseQuotient(axes);
        const Real r = scaled.norm();
        const Real limit = 1 + 0.2 * std::sin(3 * wobble.dot(q.normalized()) + 1);
        if (r <= limit) inside.push_back(centre + q);
      }
  Points points(inside.size(), 3);
  for (std::size_t i = 0; i < inside.size(); ++i)
    points.row(i) = inside[i].transpose();
  return points;
}

}  // namespace

int main() {
  const Vec3 from(0, 0, 0), to(0.1, 0, 0);
  std::printf(
      "bench_planning: minimum-penetration paths, probe 2 mm (cost sphere 3 mm), 64 "
      "samples, 5 starts\n");
  std::printf("%9s %6s %8s %12s %12s %9s %6s %7s %9s\n", "obstacles", "points", "degree",
              "straight", "cost", "deepest", "steps", "evals", "time");
  for (int count = 3; count <= 10; ++count) {
    std::vector<Obstacle> obstacles;
    std::size_t points = 0;
    for (int i = 0; i < count; ++i) {
      Obstacle o;
      o.name = "obstacle " + std::to_string(i);
      const Real x = 0.1 * (i + 1) / (count + 1);
      o.points = blob({x, (i % 2 ? 1 : -1) * 0.003, 0}, 0.006, 1300, 1000 + i);
      o.stiffness = 1 + i % 10;
      points += o.points.rows();
      obstacles.push_back(std::move(o));
    }
    for (const int degree : {3, 5}) {
      PlanOptions options;
      options.degree = degree;
      std::vector<double> times;
      PlannedPath path;
      for (int run = 0; run < 5; ++run) {
        const auto start = std::chrono::steady_clock::now();
        path = plan_path(from, to, obstacles, options);
        times.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count());
      }
      std::printf("%9d %6zu %8d %12.4g %12.4g %7.2fmm %6d %7d %7.1fms\n", count,
                  points / obstacles.size(), degree, path.straight_cost, path.cost,
                  path.max_penetration * 1000, path.iterations, path.evaluations,
                  incise::bench::median(times));
    }
  }
  return 0;
}
