#pragma once
// Seed 004's planning aid: the tool path from a start to a goal through tissue that gives way,
// as the polynomial that least makes the tool enter the obstacles, each weighted by its stiffness
// (docs/planning.md). Obstacles are point sets sampling their volume (seed 004's "phyxels": a
// tissue's mesh nodes, say), each point with its depth below the obstacle's surface; the tool tip
// is a sphere, inflated for the cost so that the path is pushed clear of the obstacles' borders
// rather than onto them. Where the sphere of radius R reaches a point x at distance d, the tool
// is depth(x) + R - d inside the obstacle there: the penetration that seed 004 minimises.
//
// The path, for s in [0, 1]:  p(s) = a + (b - a) s + s (1 - s) sum_k c_k s^k,  k = 0 .. degree - 2,
// so it always starts at a and ends at b, and c = 0 is the straight line. The cost is the mean
// over sample points of  sum_obstacles stiffness * sum_{points within R} (depth + R - d)^2  plus
// bend_weight times the mean of |p'(s) - (b - a)|^2 (zero for the straight line), minimised over
// c by gradient descent with a backtracking line search: every accepted step lowers the cost.
// Several starts (the straight line, and bends to four sides) guard against the local minima that
// seed 004 reports; the best result wins. Deterministic: no randomness anywhere.
#include <string>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim::plan {

struct Obstacle {
  std::string name;      // the tissue (a scene's label)
  Points points;         // where it is [m]
  Real stiffness = 1;    // weight of entering it (relative: 1 for the softest tissue, say)
  bool protect = false;  // a protected structure: the path must not enter it beyond the bound
  VecX depth;            // per point, how far below the surface [m]; empty: surface_depth()
};

struct PlanOptions {
  int degree = 3;              // of the polynomial: 2 (a parabola) to 7; seed 004 uses 3 and 5
  Real probe_radius = 0.002;   // the tool tip's sphere [m]
  Real inflation = 1.5;        // the cost's sphere is this many times larger
  int samples = 64;            // points along the path where the cost is evaluated
  int max_iterations = 300;    // per start
  Real bend_weight = 0.01;     // price of bending, in stiffness units: 0 bends for free
  Real penetration_bound = 0;  // [m] how deep the probe may enter a protected structure
};

struct PlannedPath {
  Vec3 from = Vec3::Zero();
  Vec3 to = Vec3::Zero();
  std::vector<Vec3> bend;              // c_0 .. c_{degree-2}
  Real straight_cost = 0;              // of the straight line
  Real cost = 0;                       // of this path
  std::vector<Real> cost_history;      // the winning start's cost after each accepted step
  int iterations = 0;                  // accepted steps, all starts together
  int evaluations = 0;                 // cost evaluations, all starts together
  Real max_penetration = 0;            // [m] deepest the probe (not inflated) enters an obstacle
  std::string deepest_obstacle;        // which ("" when it enters none)
  Real max_protected_penetration = 0;  // [m] the same over the protected structures only
  bool within_bound = true;            // max_protected_penetration <= the bound
  std::string problem;                 // when !within_bound: which structure, how deep, where

  Vec3 at(Real s) const;
  // `n` >= 2 points from `from` to `to`, evenly spaced in s.
  std::vector<Vec3> polyline(int n) const;
};

// Each point's distance to the nearest point on the set's boundary, for a set sampling a volume
// about evenly (a lattice, a mesh's nodes): a point is on the boundary when its neighbours within
// 2.5 spacings lie lopsidedly around it. 0 on the boundary.
VecX surface_depth(const Points& points);

// Points on a cubic lattice of `spacing` [m] inside the tets (of nodes): a tissue's volume sampled
// evenly, however coarse its mesh (the planner's points must be closer than its probe).
Points volume_points(const Points& nodes, const Tets& tets, Real spacing);

// Throws std::invalid_argument for options out of range or from == to.
PlannedPath plan_path(const Vec3& from, const Vec3& to, const std::vector<Obstacle>& obstacles,
                      const PlanOptions& options = {});

}  // namespace incise::sim::plan
