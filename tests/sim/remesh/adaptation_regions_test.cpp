// Regions of adaptation: contact marks exactly the tets a tool reaches (in the deformed
// configuration), Green strain matches its closed form, the surface bend marks a fold line and
// nothing on a flat or rigidly moved surface, hysteresis holds a region between its off and on
// levels without flicker, and the size fields are fine inside, graded around, infinite far away.

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "remesh_fixtures.h"
#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/adaptation_regions.h"
#include "sim/remesh/decimation.h"
#include "sim/remesh/flips.h"
#include "sim/remesh/refinement.h"

namespace incise::sim::remesh {
namespace {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

void update(AdaptationRegions& regions, const TetMesh& mesh, std::span<const Vec3> tools = {}) {
  regions.update(mesh.rest, mesh.x, mesh.tets, face_neighbours(mesh.tets), {}, tools);
}

Vec3 rest_centroid(const TetMesh& mesh, int t) {
  Vec3 c = Vec3::Zero();
  for (int k = 0; k < 4; ++k)
    c += row3(mesh.rest, mesh.tets(t, k)) / 4;
  return c;
}

// The box stretched along x by `factor`: Green strain diag((factor^2 - 1) / 2, 0, 0).
TetMesh stretched_box(Real factor) {
  TetMesh mesh = testing::unit_box();
  mesh.x.col(0) *= factor;
  return mesh;
}

// A rotation about (1, 2, 2) / 3 by 0.7 rad.
Mat3 some_rotation() {
  return Eigen::AngleAxis<Real>(0.7, Vec3(1, 2, 2) / 3).toRotationMatrix();
}

// Points on a lattice through the box and around it, to compare the fields.
std::vector<Vec3> probe_points() {
  std::vector<Vec3> points;
  for (int i = -2; i <= 12; ++i)
    for (int j = -2; j <= 12; ++j)
      for (int k = -2; k <= 12; ++k)
        points.emplace_back(0.1 * i + 0.013, 0.1 * j + 0.007, 0.1 * k + 0.011);
  return points;
}

// The keep field's region contains the refine field's, and asks for no coarser size there.
void expect_keep_covers_refine(const AdaptationRegions& regions) {
  const SizeField refine = regions.refine_field();
  const SizeField keep = regions.keep_field();
  for (const Vec3& p : probe_points()) {
    if (std::isfinite(refine(p))) {
      ASSERT_LE(keep(p), refine(p)) << p.transpose();
    }
  }
}

TEST(AdaptationRegions, GreenStrainOfAUniaxialStretchIsTheClosedForm) {
  const TetMesh mesh = stretched_box(1.1);
  const Real expected = (1.1 * 1.1 - 1) / 2;  // 0.105
  AdaptationCriteria criteria;
  criteria.strain = true;
  criteria.strain_on = 0.05;
  criteria.strain_off = 0.03;
  criteria.fine_size = 0.05;
  AdaptationRegions regions(criteria);
  update(regions, mesh);
  const SizeField refine = regions.refine_field();
  for (int t = 0; t < mesh.num_tets(); ++t) {
    EXPECT_NEAR(regions.strain()[t], expected, 1e-12);
    EXPECT_EQ(regions.marks()[t], TetMark::kHot);
    EXPECT_EQ(refine(rest_centroid(mesh, t)), 0.05);
  }

  // A rigid motion on top of the rest shape has no strain.
  TetMesh rotated = testing::unit_box();
  rotated.x = (rotated.rest * some_rotation().transpose()).rowwise() + Vec3(1, 2, 3).transpose();
  AdaptationRegions rigid(criteria);
  update(rigid, rotated);
  for (int t = 0; t < rotated.num_tets(); ++t)
    EXPECT_NEAR(rigid.strain()[t], 0, 1e-12);
  EXPECT_TRUE(rigid.balls().empty());

  criteria.strain_on = 0.2;
  criteria.strain_off = 0.15;
  AdaptationRegions high(criteria);
  update(high, mesh);
  for (int t = 0; t < mesh.num_tets(); ++t)
    EXPECT_EQ(high.marks()[t], TetMark::kCold);
  EXPECT_TRUE(high.balls().empty());
  EXPECT_EQ(high.refine_field()(Vec3(0.5, 0.5, 0.5)), kInfinity);
}

// The minimum over a barycentric lattice of step 1 / n of the distance from p to the tet: at
// least the true distance, and at most the true distance + the longest edge / n.
Real sampled_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                      int n) {
  Real best = kInfinity;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
      for (int k = 0; i + j + k <= n; ++k) {
        const int l = n - i - j - k;
        best = std::min(best, (p - (i * a + j * b + k * c + l * d) / n).norm());
      }
  return best;
}

TEST(AdaptationRegions, ContactMarksExactlyTheTetsATouchesInTheDeformedBody) {
  // The body moved rigidly: tools given in the deformed configuration must find the same tets as
  // their rest images would at rest.
  TetMesh mesh = testing::unit_box();
  const Mat3 rotation = some_rotation();
  const Vec3 shift(0.3, -0.2, 0.5);
  mesh.x = (mesh.rest * rotation.transpose()).rowwise() + shift.transpose();
  const std::vector<Vec3> rest_tools = {Vec3(0.3, 0.6, 1.04), Vec3(0.55, 0.45, 0.5)};
  std::vector<Vec3> tools;
  for (const Vec3& p : rest_tools)
    tools.push_back(rotation * p + shift);

  AdaptationCriteria criteria;
  criteria.contact = true;
  criteria.contact_radius = 0.1;
  criteria.contact_release = 0.15;
  criteria.fine_size = 0.05;
  AdaptationRegions regions(criteria);
  update(regions, mesh, tools);

  const int n = 24;
  const Real longest_edge = std::sqrt(3.0) / 4;  // a cell's diagonal
  int hot = 0;
  const SizeField refine = regions.refine_field();
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Real sampled = kInfinity;
    for (const Vec3& tool : tools) {
      sampled = std::min(
          sampled,
          sampled_distance(tool, row3(mesh.x, mesh.tets(t, 0)), row3(mesh.x, mesh.tets(t, 1)),
                           row3(mesh.x, mesh.tets(t, 2)), row3(mesh.x, mesh.tets(t, 3)), n));
    }
    if (regions.marks()[t] == TetMark::kHot) {
      ++hot;
      EXPECT_LE(sampled, criteria.contact_radius + longest_edge / n) << "tet " << t;
      EXPECT_LE(regions.tool_distance()[t], sampled + 1e-12);
      EXPECT_GE(regions.tool_distance()[t], sampled - longest_edge / n - 1e-12);
      // The balls enclose the tet at rest.
      for (int k = 0; k < 4; ++k)
        EXPECT_EQ(refine(row3(mesh.rest, mesh.tets(t, k))), 0.05);
    } else {
      EXPECT_GT(sampled, criteria.contact_radius) << "tet " << t;
    }
  }
  EXPECT_GT(hot, 0);
  EXPECT_LT(hot, mesh.num_tets() / 2);

  // The same tools at rest on the undeformed body mark the same tets.
  TetMesh at_rest = testing::unit_box();
  AdaptationRegions rest_regions(criteria);
  update(rest_regions, at_rest, rest_tools);
  EXPECT_EQ(rest_regions.marks(), regions.marks());

  // A tool away from the body marks nothing and asks for nothing.
  const std::vector<Vec3> away = {Vec3(5, 5, 5)};
  AdaptationRegions idle(criteria);
  update(idle, mesh, away);
  for (int t = 0; t < mesh.num_tets(); ++t)
    EXPECT_EQ(idle.marks()[t], TetMark::kCold);
  EXPECT_TRUE(idle.balls().empty());
  for (const Vec3& p : probe_points()) {
    ASSERT_EQ(idle.refine_field()(p), kInfinity);
  }
}

TEST(AdaptationRegions, PointTetDistanceMatchesSampling) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);
  EXPECT_EQ(point_tet_distance(Vec3(0.1, 0.1, 0.1), a, b, c, d), 0);
  EXPECT_NEAR(point_tet_distance(Vec3(0.2, 0.2, -0.3), a, b, c, d), 0.3, 1e-15);  // to a face
  EXPECT_NEAR(point_tet_distance(Vec3(2, 0, 0), a, b, c, d), 1, 1e-15);           // to a vertex
  EXPECT_NEAR(point_tet_distance(Vec3(0.5, -1, -1), a, b, c, d), std::sqrt(2.0), 1e-15);  // edge
  // Orientation does not matter.
  EXPECT_NEAR(point_tet_distance(Vec3(0.2, 0.2, -0.3), b, a, c, d), 0.3, 1e-15);
}

TEST(AdaptationRegions, BendMarksTheFoldLineAndNotAFlatOrRigidlyMovedSurface) {
  // Fold the box along the plane x = 0.5: the part beyond it turns up by 30 degrees, each
  // z-layer about its own line x = 0.5 (x' = 0.5 + u cos a, z' = z + u sin a, u = x - 0.5).
  // The map is affine on each side and every tet lies on one side, so faces stay flat: the top
  // and bottom faces bend by exactly a along x = 0.5, and (the right face keeps its normal
  // while they turn) along x = 1; the sides y = 0, 1 stay in their planes.
  const Real angle = std::numbers::pi / 6;
  TetMesh mesh = testing::unit_box();
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Real u = mesh.rest(i, 0) - 0.5;
    if (u > 0) {
      mesh.x(i, 0) = 0.5 + u * std::cos(angle);
      mesh.x(i, 2) += u * std::sin(angle);
    }
  }
  AdaptationCriteria criteria;
  criteria.curvature = true;
  criteria.bend_on = 20 * std::numbers::pi / 180;
  criteria.bend_off = 10 * std::numbers::pi / 180;
  criteria.fine_size = 0.05;
  AdaptationRegions regions(criteria);
  update(regions, mesh);

  // Brute force: the tets with a boundary face that has an edge on a fold line.
  const Tets neighbors = face_neighbours(mesh.tets);
  int expected_count = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    bool on_fold = false;
    for (int k = 0; k < 4; ++k) {
      if (neighbors(t, k) >= 0) continue;
      for (int i = 0; i < 3; ++i) {
        const Vec3 p = row3(mesh.rest, mesh.tets(t, kTetFaces[k][i]));
        const Vec3 q = row3(mesh.rest, mesh.tets(t, kTetFaces[k][(i + 1) % 3]));
        on_fold = on_fold || (p.x() == q.x() && (p.x() == 0.5 || p.x() == 1) && p.z() == q.z() &&
                              (p.z() == 0 || p.z() == 1));
      }
    }
    expected_count += on_fold;
    EXPECT_EQ(regions.marks()[t], on_fold ? TetMark::kHot : TetMark::kCold) << "tet " << t;
    if (on_fold) {
      EXPECT_NEAR(regions.bend()[t], angle, 1e-12);
    } else {
      EXPECT_LT(regions.bend()[t], 1e-12);
    }
  }
  EXPECT_GT(expected_count, 0);

  // Flat: nothing. The box's own 90 degree edges do not count; nor do they after a rigid motion.
  TetMesh flat = testing::unit_box();
  AdaptationRegions flat_regions(criteria);
  update(flat_regions, flat);
  TetMesh moved = testing::unit_box();
  moved.x = (moved.rest * some_rotation().transpose()).rowwise() + Vec3(1, 0, 0).transpose();
  AdaptationRegions moved_regions(criteria);
  update(moved_regions, moved);
  for (int t = 0; t < flat.num_tets(); ++t) {
    EXPECT_EQ(flat_regions.bend()[t], 0);
    EXPECT_LT(moved_regions.bend()[t], 1e-12);
  }
  EXPECT_TRUE(flat_regions.balls().empty());
  EXPECT_TRUE(moved_regions.balls().empty());
}

TEST(AdaptationRegions, HysteresisHoldsARegionBetweenOffAndOnWithoutFlicker) {
  AdaptationCriteria criteria;
  criteria.strain = true;
  criteria.strain_on = 0.05;
  criteria.strain_off = 0.03;
  criteria.fine_size = 0.05;
  criteria.keep_margin = 0.1;
  criteria.merge_distance = 0.3;
  AdaptationRegions regions(criteria);
  const TetMesh unstrained = testing::unit_box();
  const auto box_with_strain = [](Real e) { return stretched_box(std::sqrt(1 + 2 * e)); };
  const auto all_centroids_refined = [&]() {
    const SizeField refine = regions.refine_field();
    for (int t = 0; t < unstrained.num_tets(); ++t)
      if (refine(rest_centroid(unstrained, t)) != criteria.fine_size) return false;
    return true;
  };

  update(regions, box_with_strain(0.0));
  EXPECT_TRUE(regions.balls().empty());

  update(regions, box_with_strain(0.06));  // past on: refine
  ASSERT_FALSE(regions.balls().empty());
  EXPECT_TRUE(all_centroids_refined());
  expect_keep_covers_refine(regions);
  const std::vector<RegionBall> refined = regions.balls();
  // merge_distance gathers the 320 tets into a few balls.
  EXPECT_LT(refined.size(), 40u);

  const auto same_balls = [&]() {
    if (regions.balls().size() != refined.size()) return false;
    for (size_t i = 0; i < refined.size(); ++i) {
      if (regions.balls()[i].center != refined[i].center ||
          regions.balls()[i].radius != refined[i].radius) {
        return false;
      }
    }
    return true;
  };
  // Oscillating between off and on: the same balls every time, still refined everywhere.
  for (Real e : {0.04, 0.06, 0.04, 0.031}) {
    update(regions, box_with_strain(e));
    for (TetMark mark : regions.marks())
      EXPECT_EQ(mark, e >= 0.05 ? TetMark::kHot : TetMark::kWarm);
    EXPECT_TRUE(same_balls()) << "strain " << e;
    EXPECT_TRUE(all_centroids_refined()) << "strain " << e;
    expect_keep_covers_refine(regions);
  }

  update(regions, box_with_strain(0.02));  // below off: released
  EXPECT_TRUE(regions.balls().empty());
  for (const Vec3& p : probe_points()) {
    ASSERT_EQ(regions.refine_field()(p), kInfinity);
    ASSERT_EQ(regions.keep_field()(p), kInfinity);
  }

  // Between off and on without having been past on: never refined.
  update(regions, box_with_strain(0.04));
  EXPECT_TRUE(regions.balls().empty());
}

TEST(AdaptationRegions, SizeFieldsAreFineInsideGradedAroundAndInfiniteFar) {
  TetMesh mesh = testing::unit_box();
  AdaptationCriteria criteria;
  criteria.contact = true;
  criteria.contact_radius = 0.05;
  criteria.contact_release = 0.05;
  criteria.fine_size = 0.05;
  criteria.coarse_size = 0.2;
  criteria.grading = 0.5;
  criteria.keep_margin = 0.1;
  criteria.merge_distance = 1;  // one ball
  AdaptationRegions regions(criteria);
  const std::vector<Vec3> tools = {Vec3(0.55, 0.45, 0.4)};
  update(regions, mesh, tools);
  ASSERT_EQ(regions.balls().size(), 1u);
  const RegionBall ball = regions.balls()[0];
  const SizeField refine = regions.refine_field();
  const SizeField keep = regions.keep_field();
  EXPECT_EQ(refine(ball.center), 0.05);
  const Vec3 out = Vec3(1, 1, 1).normalized();
  // Graded band: fine + grading * d while below coarse, i.e. d < (0.2 - 0.05) / 0.5 = 0.3.
  for (Real d : {0.0, 0.05, 0.1, 0.2, 0.29}) {
    const Vec3 p = ball.center + (ball.radius + d) * out;
    EXPECT_NEAR(refine(p), 0.05 + 0.5 * d, 1e-12) << d;
    EXPECT_NEAR(keep(p), 0.05 + 0.5 * std::max(Real(0), d - 0.1), 1e-12) << d;
  }
  EXPECT_EQ(refine(ball.center + (ball.radius + 0.31) * out), kInfinity);
  EXPECT_NEAR(keep(ball.center + (ball.radius + 0.31) * out), 0.05 + 0.5 * 0.21, 1e-12);
  EXPECT_EQ(keep(ball.center + (ball.radius + 0.41) * out), kInfinity);
  EXPECT_EQ(refine(Vec3(10, 10, 10)), kInfinity);
  // The hint holds every point where the refine field is finite (the ball and its band, 0.3),
  // and not much more.
  const std::optional<RegionHint> hint = regions.refine_hint();
  ASSERT_TRUE(hint.has_value());
  std::mt19937 random(5);
  std::uniform_real_distribution<Real> coordinate(-1, 2);
  int finite = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(coordinate(random), coordinate(random), coordinate(random));
    if (!std::isfinite(refine(p))) continue;
    ++finite;
    EXPECT_LE((p - hint->center).norm(), hint->radius) << p.transpose();
  }
  EXPECT_GT(finite, 0);
  EXPECT_LE(hint->radius, std::sqrt(3.0) * (ball.radius + 0.3) + 1e-12);

  // A snapshot: moving the tool away later does not change a field already handed out.
  const std::vector<Vec3> away = {Vec3(5, 5, 5)};
  update(regions, mesh, away);
  EXPECT_TRUE(regions.balls().empty());
  EXPECT_EQ(refine(ball.center), 0.05);
}

// The mesh's slots as plain arrays, with x = rest (an undeformed body).
struct Slots {
  Points rest;
  Tets tets, neighbors;
  std::vector<char> alive;
};
Slots slots_of(const RemeshMesh& mesh) {
  Slots s;
  s.rest.resize(mesh.num_vertex_slots(), 3);
  for (int v = 0; v < mesh.num_vertex_slots(); ++v)
    s.rest.row(v) = mesh.point(v).transpose();
  s.tets.resize(mesh.num_tet_slots(), 4);
  s.neighbors.resize(mesh.num_tet_slots(), 4);
  s.alive.assign(mesh.num_tet_slots(), 0);
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    s.alive[t] = mesh.tet_alive(t);
    for (int k = 0; k < 4; ++k) {
      s.tets(t, k) = mesh.tet(t)[k];
      s.neighbors(t, k) = mesh.neighbor(t, k);
    }
  }
  return s;
}

TEST(AdaptationRegions, DrivesRefinementAndDecimationAcrossRemeshing) {
  RemeshMesh mesh(testing::jittered_two_label_box(3));
  make_constrained_delaunay(mesh);
  const int original_vertices = mesh.num_vertices();
  AdaptationCriteria criteria;
  criteria.contact = true;
  criteria.contact_radius = 0.05;
  criteria.contact_release = 0.15;
  criteria.fine_size = 0.1;
  criteria.keep_margin = 0.1;
  criteria.merge_distance = 1;
  AdaptationRegions regions(criteria);
  const auto update_on = [&](const Vec3& tool) {
    const Slots s = slots_of(mesh);
    regions.update(s.rest, s.rest, s.tets, s.neighbors, s.alive, std::span<const Vec3>(&tool, 1));
  };

  update_on(Vec3(0.5, 0.5, 1.0));  // touching the top face
  ASSERT_FALSE(regions.balls().empty());
  RefinementSettings settings;
  settings.l_min = 0.03;
  refine(mesh, regions.refine_field(), settings);
  const int refined_vertices = mesh.num_vertices();
  EXPECT_GT(refined_vertices, original_vertices);
  const std::vector<RegionBall> balls = regions.balls();

  // The tets are new, the region is the same: the touched tets are still covered, and with the
  // tool lifted to between the on and off distances it is held as it was.
  for (const Vec3& tool : {Vec3(0.5, 0.5, 1.0), Vec3(0.5, 0.5, 1.1)}) {
    update_on(tool);
    ASSERT_EQ(regions.balls().size(), balls.size());
    for (size_t i = 0; i < balls.size(); ++i) {
      EXPECT_EQ(regions.balls()[i].center, balls[i].center);
      EXPECT_EQ(regions.balls()[i].radius, balls[i].radius);
    }
    // Nothing inside the keep region is queued. A circumcentre of a region tet may lie outside
    // it (refinement.h); those vertices are the only ones the decimator may take back.
    int outside = 0;
    for (int v = mesh.num_original_vertices(); v < mesh.num_vertex_slots(); ++v) {
      if (mesh.vertex_alive(v) && !std::isfinite(regions.keep_field()(mesh.point(v)))) ++outside;
    }
    EXPECT_LT(outside, (refined_vertices - original_vertices) / 4);
    Decimator decimator;
    EXPECT_EQ(decimator.collect(mesh, regions.keep_field()), outside);
  }

  // Tool gone: released, and decimation removes every inserted vertex.
  update_on(Vec3(5, 5, 5));
  EXPECT_TRUE(regions.balls().empty());
  Decimator decimator;
  EXPECT_EQ(decimator.collect(mesh, regions.keep_field()), refined_vertices - original_vertices);
  for (int round = 0; round < 100 && decimator.pending() > 0; ++round)
    decimator.step(mesh, regions.keep_field(), 1000);
  EXPECT_EQ(mesh.num_vertices(), original_vertices);
}

TEST(AdaptationRegions, RejectsBadCriteriaAndInput) {
  AdaptationCriteria criteria;
  EXPECT_THROW(AdaptationRegions{criteria}, std::invalid_argument);  // fine_size 0
  criteria.fine_size = 0.05;
  criteria.strain = true;
  criteria.strain_off = 0.1;  // above on
  EXPECT_THROW(AdaptationRegions{criteria}, std::invalid_argument);
  criteria.strain_off = 0.03;
  criteria.contact = true;
  criteria.contact_radius = 0.2;
  criteria.contact_release = 0.1;
  EXPECT_THROW(AdaptationRegions{criteria}, std::invalid_argument);
  criteria.contact_release = 0.3;
  criteria.coarse_size = 0.01;
  EXPECT_THROW(AdaptationRegions{criteria}, std::invalid_argument);
  criteria.coarse_size = kInfinity;
  AdaptationRegions regions(criteria);

  const TetMesh mesh = testing::unit_box();
  const Tets neighbors = face_neighbours(mesh.tets);
  const Points short_x = mesh.x.topRows(3);
  EXPECT_THROW(regions.update(mesh.rest, short_x, mesh.tets, neighbors, {}, {}),
               std::invalid_argument);
  const std::vector<char> alive(3, 1);
  EXPECT_THROW(regions.update(mesh.rest, mesh.x, mesh.tets, neighbors, alive, {}),
               std::invalid_argument);
  Tets bad = mesh.tets;
  bad(0, 0) = mesh.num_nodes();
  EXPECT_THROW(regions.update(mesh.rest, mesh.x, bad, neighbors, {}, {}), std::invalid_argument);
  Tets inverted = mesh.tets;
  std::swap(inverted(5, 0), inverted(5, 1));
  EXPECT_THROW(regions.update(mesh.rest, mesh.x, inverted, neighbors, {}, {}),
               std::invalid_argument);
  // A dead slot is not read, whatever it holds.
  std::vector<char> all_but_five(mesh.num_tets(), 1);
  all_but_five[5] = 0;
  EXPECT_NO_THROW(regions.update(mesh.rest, mesh.x, inverted, neighbors, all_but_five, {}));
  EXPECT_EQ(regions.marks()[5], TetMark::kCold);
}

}  // namespace
}  // namespace incise::sim::remesh
