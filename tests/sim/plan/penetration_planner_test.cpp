// Seed 004's planning aid (sim/plan/penetration_planner.h) on point-set obstacles built here:
// the straight line when nothing is in the way, a larger bend around a stiffer obstacle, a cost
// that never rises, and a precise report when no path stays within the bound.
#include "sim/plan/penetration_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace incise::sim::plan {
namespace {

// A ball of points on a cubic lattice of spacing h (a tissue's nodes, say).
Points ball(const Vec3& centre, Real radius, Real h) {
  std::vector<Vec3> inside;
  const int n = static_cast<int>(std::ceil(radius / h));
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Vec3 offset(i * h, j * h, k * h);
        if (offset.norm() <= radius) inside.push_back(centre + offset);
      }
  Points points(inside.size(), 3);
  for (std::size_t i = 0; i < inside.size(); ++i)
    points.row(i) = inside[i].transpose();
  return points;
}

Obstacle obstacle(const std::string& name, Points points, Real stiffness, bool protect = false) {
  Obstacle o;
  o.name = name;
  o.points = std::move(points);
  o.stiffness = stiffness;
  o.protect = protect;
  return o;
}

// Largest distance of the path from the straight line between its ends.
Real largest_offset(const PlannedPath& path) {
  const Vec3 dir = (path.to - path.from).normalized();
  Real largest = 0;
  for (const auto& p : path.polyline(201)) {
    const Vec3 rel = p - path.from;
    largest = std::max(largest, (rel - rel.dot(dir) * dir).norm());
  }
  return largest;
}

const Vec3 kFrom(0, 0, 0);
const Vec3 kTo(0.1, 0, 0);

TEST(PenetrationPlanner, NothingInTheWayGivesTheStraightLine) {
  // An obstacle well off the line: the straight line costs nothing and is kept, exactly.
  const std::vector<Obstacle> obstacles = {
      obstacle("aside", ball({0.05, 0.03, 0}, 0.01, 0.002), 5.0)};
  for (const int degree : {3, 5}) {
    PlanOptions options;
    options.degree = degree;
    const auto path = plan_path(kFrom, kTo, obstacles, options);
    EXPECT_EQ(path.straight_cost, 0);
    EXPECT_EQ(path.cost, 0);
    ASSERT_EQ(path.bend.size(), static_cast<std::size_t>(degree - 1));
    for (const auto& c : path.bend)
      EXPECT_EQ(c.norm(), 0);
    EXPECT_EQ(path.at(0.37), kFrom + 0.37 * (kTo - kFrom));
    EXPECT_TRUE(path.within_bound);
    EXPECT_EQ(path.max_penetration, 0);
  }
}

TEST(PenetrationPlanner, ThePathStartsAndEndsWhereAsked) {
  const std::vector<Obstacle> obstacles = {
      obstacle("blob", ball({0.05, 0.003, 0}, 0.012, 0.002), 1.0)};
  const auto path = plan_path(kFrom, kTo, obstacles);
  EXPECT_LT((path.at(0) - kFrom).norm(), 1e-15);
  EXPECT_LT((path.at(1) - kTo).norm(), 1e-15);
  EXPECT_GT(largest_offset(path), 0.005) << "the path did not leave the line through the blob";
}

TEST(PenetrationPlanner, BendsFurtherAroundAStifferObstacle) {
  // The same blob across the line (its centre 3 mm off it), soft and then stiff: bending costs
  // the same, so the stiffer the blob, the further the path keeps out of it.
  const auto blob = ball({0.05, 0.003, 0}, 0.012, 0.002);
  PlanOptions options;
  options.bend_weight = 1.0;
  const auto soft = plan_path(kFrom, kTo, {obstacle("soft", blob, 1.0)}, options);
  const auto stiff = plan_path(kFrom, kTo, {obstacle("stiff", blob, 100.0)}, options);
  EXPECT_GT(largest_offset(stiff), largest_offset(soft) + 0.002)
      << "soft " << largest_offset(soft) << " m, stiff " << largest_offset(stiff) << " m";
  EXPECT_LT(stiff.max_penetration, soft.max_penetration);
  // It goes round the side the blob leaves open (its centre is at +y): towards -y.
  EXPECT_LT(stiff.at(0.5).y(), 0);
}

TEST(PenetrationPlanner, TheCostNeverRisesAndEndsBelowTheStraightLine) {
  std::vector<Obstacle> obstacles;
  for (int i = 0; i < 4; ++i) {
    obstacles.push_back(obstacle(
        "blob " + std::to_string(i),
        ball({0.02 + 0.02 * i, (i % 2 ? 1 : -1) * 0.004, 0.001 * i}, 0.008, 0.0015), 1.0 + 3 * i));
  }
  for (const int degree : {3, 5}) {
    PlanOptions options;
    options.degree = degree;
    const auto path = plan_path(kFrom, kTo, obstacles, options);
    ASSERT_GE(path.cost_history.size(), 2u);
    for (std::size_t i = 1; i < path.cost_history.size(); ++i)
      EXPECT_LE(path.cost_history[i], path.cost_history[i - 1])
          << "degree " << degree << ", step " << i;
    EXPECT_EQ(path.cost, path.cost_history.back());
    EXPECT_LT(path.cost, 0.5 * path.straight_cost) << "degree " << degree;
  }
}

TEST(PenetrationPlanner, IsDeterministic) {
  const std::vector<Obstacle> obstacles = {
      obstacle("blob", ball({0.05, 0.002, 0.001}, 0.01, 0.002), 3.0)};
  const auto a = plan_path(kFrom, kTo, obstacles);
  const auto b = plan_path(kFrom, kTo, obstacles);
  EXPECT_EQ(a.cost, b.cost);
  for (std::size_t k = 0; k < a.bend.size(); ++k)
    EXPECT_EQ(a.bend[k], b.bend[k]);
}

TEST(PenetrationPlanner, SaysWhenNoPathStaysWithinTheBound) {
  // The goal lies inside the protected structure: every path ends in it.
  const std::vector<Obstacle> obstacles = {
      obstacle("artery", ball({0.1, 0, 0}, 0.006, 0.001), 50.0, true)};
  PlanOptions options;
  options.penetration_bound = 0.0005;
  const auto path = plan_path(kFrom, kTo, obstacles, options);
  EXPECT_FALSE(path.within_bound);
  EXPECT_GT(path.max_protected_penetration, options.penetration_bound);
  EXPECT_NE(path.problem.find("\"artery\""), std::string::npos) << path.problem;
  EXPECT_NE(path.problem.find("within 0.5 mm"), std::string::npos) << path.problem;

  // A protected structure beside the way is cleared, and the path is within the bound.
  const std::vector<Obstacle> beside = {
      obstacle("nerve", ball({0.05, 0.004, 0}, 0.003, 0.0005), 50.0, true)};
  const auto clear = plan_path(kFrom, kTo, beside, options);
  EXPECT_TRUE(clear.within_bound) << clear.problem;
  EXPECT_LE(clear.max_protected_penetration, options.penetration_bound);
}

TEST(SurfaceDepth, OfALatticeBallIsTheDistanceToItsSphere) {
  const Real radius = 0.01, h = 0.001;
  const Vec3 centre(0.02, -0.01, 0.005);
  const auto points = ball(centre, radius, h);
  const auto depth = surface_depth(points);
  ASSERT_EQ(depth.size(), points.rows());
  int checked = 0;
  for (int i = 0; i < points.rows(); ++i) {
    // The lattice's boundary lies within a spacing of the sphere and is found to about two.
    const Real exact = radius - (row3(points, i) - centre).norm();
    EXPECT_NEAR(depth[i], exact, 2.5 * h) << i;
    checked += exact > 0.5 * radius;
  }
  EXPECT_GT(checked, 50);
  EXPECT_NEAR(depth.maxCoeff(), radius, 2.5 * h);
  EXPECT_EQ(depth.minCoeff(), 0);
}

TEST(VolumePoints, FillACubeOfSixTetsOnceEach) {
  // The unit cube [0, 2 cm]^3 as six tets around its diagonal; a 2 mm lattice: 11^3 points,
  // each once although many lie on faces the tets share.
  Points nodes(8, 3);
  for (int i = 0; i < 8; ++i)
    nodes.row(i) << 0.02 * (i & 1), 0.02 * ((i >> 1) & 1), 0.02 * ((i >> 2) & 1);
  Tets tets(6, 4);
  tets << 0, 1, 3, 7, 0, 1, 5, 7, 0, 2, 3, 7, 0, 2, 6, 7, 0, 4, 5, 7, 0, 4, 6, 7;
  const auto points = volume_points(nodes, tets, 0.002);
  EXPECT_EQ(points.rows(), 11 * 11 * 11);
  EXPECT_GE(points.minCoeff(), -1e-12);
  EXPECT_LE(points.maxCoeff(), 0.02 + 1e-12);
  // Three of the six tets hold half the cube: about half the points, give or take a face's.
  Tets half(3, 4);
  half << 0, 1, 3, 7, 0, 1, 5, 7, 0, 4, 5, 7;
  const auto some = volume_points(nodes, half, 0.002);
  EXPECT_GT(some.rows(), 11 * 11 * 11 / 2 - 11 * 11);
  EXPECT_LT(some.rows(), 11 * 11 * 11 / 2 + 2 * 11 * 11);
}

TEST(PenetrationPlanner, RefusesOptionsOutOfRange) {
  PlanOptions options;
  options.degree = 8;
  EXPECT_THROW(plan_path(kFrom, kTo, {}, options), std::invalid_argument);
  EXPECT_THROW(plan_path(kFrom, kFrom, {}), std::invalid_argument);
  options = {};
  options.inflation = 0.5;
  EXPECT_THROW(plan_path(kFrom, kTo, {}, options), std::invalid_argument);
  const auto bad = obstacle("bad", ball({0.05, 0, 0}, 0.002, 0.001), -1.0);
  EXPECT_THROW(plan_path(kFrom, kTo, {bad}), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::plan
