// SurfaceBvh against a brute-force loop over all live triangles, on a deformed box boundary and
// a jittered sphere: after the build, after refits, after removing and adding triangles, and
// after a rebuild; plus refit == fresh build, the looseness measure, and bad input.

#include "sim/collide/surface_bvh.h"

#include <algorithm>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "collide_fixtures.h"
#include "sim/collide/mesh_surface_faces.h"
#include "sim/collide/shape_triangle_contact.h"
#include "sim/collide/triangle_geometry.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"

namespace incise::sim::collide {
namespace {

using testing::TestSurface;

Vec3 corner(const Points& points, const SurfaceBvh& bvh, int slot, int k) {
  return row3(points, bvh.triangle(slot)[k]);
}

std::vector<int> brute_overlapping(const Points& points, const SurfaceBvh& bvh,
                                   const Sphere& sphere) {
  std::vector<int> out;
  for (int s = 0; s < bvh.num_slots(); ++s) {
    if (!bvh.is_live(s)) continue;
    const Vec3 a = corner(points, bvh, s, 0), b = corner(points, bvh, s, 1),
               c = corner(points, bvh, s, 2);
    const Vec3 w = closest_point_barycentric(sphere.centre, a, b, c);
    if ((w[0] * a + w[1] * b + w[2] * c - sphere.centre).norm() <= sphere.radius) out.push_back(s);
  }
  return out;
}

std::vector<int> brute_overlapping(const Points& points, const SurfaceBvh& bvh,
                                   const Capsule& capsule) {
  std::vector<int> out;
  for (int s = 0; s < bvh.num_slots(); ++s) {
    if (!bvh.is_live(s)) continue;
    if (segment_triangle_closest(capsule.a, capsule.b, corner(points, bvh, s, 0),
                                 corner(points, bvh, s, 1), corner(points, bvh, s, 2))
            .distance <= capsule.radius) {
      out.push_back(s);
    }
  }
  return out;
}

template <class Shape>
std::vector<Contact> brute_contacts(const Points& points, const SurfaceBvh& bvh,
                                    const Shape& shape) {
  std::vector<Contact> out;
  for (int s = 0; s < bvh.num_slots(); ++s) {
    if (!bvh.is_live(s)) continue;
    Contact contact;
    bool touches = false;
    if constexpr (std::is_same_v<Shape, Sphere>) {
      touches = sphere_triangle_contact(shape, corner(points, bvh, s, 0), corner(points, bvh, s, 1),
                                        corner(points, bvh, s, 2), contact);
    } else {
      touches =
          capsule_triangle_contact(shape, corner(points, bvh, s, 0), corner(points, bvh, s, 1),
                                   corner(points, bvh, s, 2), contact);
    }
    if (touches) {
      contact.triangle = s;
      out.push_back(contact);
    }
  }
  return out;
}

// Earliest sweep time over all live triangles (2 = no hit).
Real brute_sweep(const Points& points, const SurfaceBvh& bvh, const Sphere& sphere,
                 const Vec3& c1) {
  Real best = 2;
  for (int s = 0; s < bvh.num_slots(); ++s) {
    if (!bvh.is_live(s)) continue;
    SweepContact contact;
    if (sweep_sphere_triangle(sphere.centre, c1, sphere.radius, corner(points, bvh, s, 0),
                              corner(points, bvh, s, 1), corner(points, bvh, s, 2), contact)) {
      best = std::min(best, contact.time);
    }
  }
  return best;
}

std::vector<int> sorted(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  return v;
}

void expect_same_contacts(std::vector<Contact> tree, std::vector<Contact> brute) {
  const auto by_triangle = [](const Contact& x, const Contact& y) {
    return x.triangle < y.triangle;
  };
  std::sort(tree.begin(), tree.end(), by_triangle);
  std::sort(brute.begin(), brute.end(), by_triangle);
  ASSERT_EQ(tree.size(), brute.size());
  for (std::size_t k = 0; k < tree.size(); ++k) {
    EXPECT_EQ(tree[k].triangle, brute[k].triangle);
    EXPECT_EQ(tree[k].depth, brute[k].depth);
    EXPECT_EQ(tree[k].point, brute[k].point);
    EXPECT_EQ(tree[k].normal, brute[k].normal);
    EXPECT_EQ(tree[k].barycentric, brute[k].barycentric);
    EXPECT_GT(tree[k].depth, 0);
    EXPECT_NEAR(tree[k].normal.norm(), 1, 1e-12);
  }
}

// Random spheres, capsules and sweeps within the surface's bounding box (radii a few percent of
// its size, so that each query touches a handful of triangles or none); returns how many
// queries found something, so a test can check it exercised real overlaps.
int check_against_brute_force(const Points& points, const SurfaceBvh& bvh, unsigned seed) {
  const Box3 bounds(points.colwise().minCoeff().transpose(),
                    points.colwise().maxCoeff().transpose());
  const Real size = bounds.sizes().maxCoeff();
  std::mt19937 random(seed);
  std::uniform_real_distribution<Real> unit(0, 1);
  const auto random_point = [&] {
    return Vec3(bounds.min() +
                bounds.sizes().cwiseProduct(Vec3(unit(random), unit(random), unit(random))));
  };
  std::vector<int> slots;
  std::vector<Contact> contacts;
  int found = 0;
  for (int q = 0; q < 60; ++q) {
    const Sphere sphere{random_point(), size * (0.01 + 0.1 * unit(random))};
    bvh.overlapping_triangles(points, sphere, slots);
    EXPECT_EQ(sorted(slots), brute_overlapping(points, bvh, sphere));
    found += !slots.empty();
    bvh.contacts(points, sphere, contacts);
    expect_same_contacts(contacts, brute_contacts(points, bvh, sphere));

    const Vec3 a = random_point();
    const Capsule capsule{a, a + 0.3 * (random_point() - a), size * (0.01 + 0.05 * unit(random))};
    bvh.overlapping_triangles(points, capsule, slots);
    EXPECT_EQ(sorted(slots), brute_overlapping(points, bvh, capsule));
    bvh.contacts(points, capsule, contacts);
    expect_same_contacts(contacts, brute_contacts(points, bvh, capsule));

    const Sphere start{random_point(), size * 0.02};
    const Vec3 c1 = random_point();
    SweepHit hit;
    const bool hits = bvh.sweep(points, start, c1, hit);
    const Real brute = brute_sweep(points, bvh, start, c1);
    EXPECT_EQ(hits, brute <= 1);
    if (hits) {
      EXPECT_EQ(hit.time, brute);
      EXPECT_TRUE(bvh.is_live(hit.triangle));
      // At the first touch the distance is r; a sphere touching at the start may be closer.
      const Real distance = (start.centre + hit.time * (c1 - start.centre) - hit.point).norm();
      if (hit.time > 0) {
        EXPECT_NEAR(distance, start.radius, 1e-9 * size);
      } else {
        EXPECT_LE(distance, start.radius);
      }
    }
  }
  return found;
}

std::vector<TestSurface> surfaces() {
  return {testing::deformed_box_surface(Vec3(0.08, 0.06, 0.04), Vec3i(8, 6, 4), 0.002, 1),
          testing::jittered_sphere_surface(Vec3(0.01, 0, 0), 0.05, 24, 32, 0.05, 2)};
}

TEST(SurfaceBvh, QueriesMatchBruteForceAfterBuildAndRefits) {
  for (TestSurface surface : surfaces()) {
    SurfaceBvh bvh;
    bvh.build(surface.points, surface.triangles);
    EXPECT_EQ(bvh.num_nodes(), 2 * surface.triangles.rows() - 1);
    EXPECT_GT(check_against_brute_force(surface.points, bvh, 3), 10);
    // A few steps of a moving, twisting surface, refitted each step.
    for (int step = 1; step <= 3; ++step) {
      testing::displace(surface.points, [&](const Vec3& p) {
        return Vec3(0.05 * step * p.y(), -0.03 * p.z(), 0.004 * std::sin(80 * p.x()));
      });
      bvh.refit(surface.points);
      check_against_brute_force(surface.points, bvh, 10 + step);
    }
  }
}

TEST(SurfaceBvh, RefitOfAMovedSurfaceAnswersLikeAFreshBuild) {
  for (TestSurface surface : surfaces()) {
    SurfaceBvh refitted;
    refitted.build(surface.points, surface.triangles);
    testing::displace(surface.points, [](const Vec3& p) {
      return Vec3(0.2 * p.z(), 0.01 * std::cos(50 * p.x()), -0.1 * p.y());
    });
    refitted.refit(surface.points);
    SurfaceBvh fresh;
    fresh.build(surface.points, surface.triangles);
    std::mt19937 random(5);
    std::uniform_real_distribution<Real> unit(-0.06, 0.06);
    std::vector<int> a, b;
    std::vector<Contact> ca, cb;
    for (int q = 0; q < 100; ++q) {
      const Sphere sphere{Vec3(unit(random), unit(random), unit(random)), 0.01};
      refitted.overlapping_triangles(surface.points, sphere, a);
      fresh.overlapping_triangles(surface.points, sphere, b);
      EXPECT_EQ(sorted(a), sorted(b));
      refitted.contacts(surface.points, sphere, ca);
      fresh.contacts(surface.points, sphere, cb);
      expect_same_contacts(ca, cb);
    }
  }
}

TEST(SurfaceBvh, RemovingAndAddingTrianglesKeepsQueriesExact) {
  for (TestSurface surface : surfaces()) {
    SurfaceBvh bvh;
    bvh.build(surface.points, surface.triangles);
    const int n = static_cast<int>(surface.triangles.rows());
    std::mt19937 random(7);
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i)
      order[i] = i;
    std::shuffle(order.begin(), order.end(), random);
    // A cut: a quarter of the triangles go.
    const int removed = n / 4;
    for (int k = 0; k < removed; ++k)
      bvh.remove_triangle(order[k]);
    EXPECT_EQ(bvh.num_live_triangles(), n - removed);
    EXPECT_EQ(bvh.num_nodes(), 2 * (n - removed) - 1);
    check_against_brute_force(surface.points, bvh, 21);
    // The cut surface: new triangles (here the removed ones again, flipped, as new slots).
    for (int k = 0; k < removed; ++k) {
      const Vec3i t = surface.triangles.row(order[k]).transpose();
      EXPECT_EQ(bvh.add_triangle(surface.points, Vec3i(t[0], t[2], t[1])), n + k);
    }
    EXPECT_EQ(bvh.num_live_triangles(), n);
    EXPECT_EQ(bvh.num_nodes(), 2 * n - 1);
    check_against_brute_force(surface.points, bvh, 22);
    // Then the surface moves: refit still covers the inserted leaves.
    testing::displace(surface.points, [](const Vec3& p) { return Vec3(0.1 * p.y(), 0, 0.01); });
    bvh.refit(surface.points);
    check_against_brute_force(surface.points, bvh, 23);
    // A rebuild keeps the slots.
    bvh.rebuild(surface.points);
    EXPECT_DOUBLE_EQ(bvh.looseness(), 1);
    check_against_brute_force(surface.points, bvh, 24);
  }
}

TEST(SurfaceBvh, EmptyingAndRefillingTheTree) {
  TestSurface surface = testing::flat_sheet(0.01, 2, 0);
  SurfaceBvh bvh;
  bvh.build(surface.points, surface.triangles);
  for (int s = 0; s < 8; ++s)
    bvh.remove_triangle(s);
  EXPECT_EQ(bvh.num_live_triangles(), 0);
  std::vector<int> slots{1, 2};
  bvh.overlapping_triangles(surface.points, Sphere{Vec3::Zero(), 1}, slots);
  EXPECT_TRUE(slots.empty());
  bvh.refit(surface.points);
  EXPECT_EQ(bvh.add_triangle(surface.points, Vec3i(0, 1, 4)), 8);
  EXPECT_EQ(bvh.add_triangle(surface.points, Vec3i(4, 5, 8)), 9);
  bvh.overlapping_triangles(surface.points, Sphere{Vec3::Zero(), 1}, slots);
  EXPECT_EQ(sorted(slots), (std::vector<int>{8, 9}));
}

TEST(SurfaceBvh, LoosenessIsScaleFreeGrowsUnderLargeDeformationAndResetsOnRebuild) {
  for (TestSurface surface : surfaces()) {
    SurfaceBvh bvh;
    bvh.build(surface.points, surface.triangles);
    EXPECT_DOUBLE_EQ(bvh.looseness(), 1);
    // A uniform scaling and a translation change no box's relative size.
    Points moved = surface.points;
    for (int i = 0; i < moved.rows(); ++i) {
      moved.row(i) = (3 * row3(surface.points, i) + Vec3(1, -2, 0.5)).transpose();
    }
    bvh.refit(moved);
    EXPECT_NEAR(bvh.looseness(), 1, 1e-9);
    EXPECT_FALSE(bvh.needs_rebuild());
    // A large deformation that scatters neighbours: every point jumps by up to a third of the
    // body's size, so each subtree's box swells towards the whole body.
    std::mt19937 random(9);
    std::uniform_real_distribution<Real> jump(-0.03, 0.03);
    testing::displace(surface.points,
                      [&](const Vec3&) { return Vec3(jump(random), jump(random), jump(random)); });
    bvh.refit(surface.points);
    EXPECT_GT(bvh.looseness(), SurfaceBvh::kDefaultLooseness);
    EXPECT_TRUE(bvh.needs_rebuild());
    check_against_brute_force(surface.points, bvh, 31);  // loose, but still exact
    bvh.rebuild(surface.points);
    EXPECT_DOUBLE_EQ(bvh.looseness(), 1);
    EXPECT_FALSE(bvh.needs_rebuild());
  }
}

TEST(SurfaceBvh, ManyRemovalsAskForARebuild) {
  TestSurface surface = testing::flat_sheet(0.01, 10, 0);
  SurfaceBvh bvh;
  bvh.build(surface.points, surface.triangles);
  for (int s = 0; s < 120; ++s)
    bvh.remove_triangle(s);
  EXPECT_TRUE(bvh.needs_rebuild(1e9));  // over half the node slots are free
  bvh.rebuild(surface.points);
  EXPECT_EQ(bvh.num_nodes(), 2 * 80 - 1);
  EXPECT_FALSE(bvh.needs_rebuild(1e9));
}

TEST(SurfaceBvh, OnMeshNodesAnswersLikeOnSurfaceVertices) {
  // A tree over the mesh's deformed x with the faces mapped to mesh nodes gives the same
  // contacts (same triangle numbers) as one over the surface's own vertex array.
  TetMesh mesh = make_box_mesh(Vec3(0.04, 0.03, 0.02), Vec3i(4, 3, 2));
  const BoundarySurface surface = boundary_surface(mesh);
  testing::displace(mesh.x, [](const Vec3& p) { return Vec3(0.1 * p.z(), 0, -0.2 * p.x()); });
  SurfaceBvh on_mesh;
  on_mesh.build(mesh.x, mesh_surface_faces(surface));
  Points V, N;
  surface_vertices(surface, mesh.x, V, N);
  SurfaceBvh on_surface;
  on_surface.build(V, surface.faces);
  std::mt19937 random(4);
  std::uniform_real_distribution<Real> unit(-0.01, 0.05);
  std::vector<Contact> a, b;
  int touching = 0;
  for (int q = 0; q < 100; ++q) {
    const Sphere sphere{Vec3(unit(random), unit(random), unit(random)), 0.006};
    on_mesh.contacts(mesh.x, sphere, a);
    on_surface.contacts(V, sphere, b);
    expect_same_contacts(a, b);
    touching += !a.empty();
  }
  EXPECT_GT(touching, 10);
}

TEST(SurfaceBvh, BadInputIsRejectedWithAPreciseMessage) {
  TestSurface surface = testing::flat_sheet(0.01, 2, 0);
  SurfaceBvh bvh;
  Triangles bad = surface.triangles;
  bad(3, 1) = 9;
  try {
    bvh.build(surface.points, bad);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "SurfaceBvh::build: triangle 3 has index 9 outside [0, 9)");
  }
  Points nan_points = surface.points;
  nan_points(4, 2) = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_THROW(bvh.build(nan_points, surface.triangles), std::invalid_argument);
  bvh.build(surface.points, surface.triangles);
  EXPECT_THROW(bvh.refit(surface.points.topRows(5)), std::invalid_argument);
  EXPECT_THROW(bvh.add_triangle(surface.points, Vec3i(0, 1, -1)), std::invalid_argument);
  bvh.remove_triangle(2);
  try {
    bvh.remove_triangle(2);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "SurfaceBvh::remove_triangle: slot 2 is already removed");
  }
  EXPECT_THROW(bvh.remove_triangle(8), std::invalid_argument);
  std::vector<Contact> contacts;
  EXPECT_THROW(bvh.contacts(surface.points, Sphere{Vec3::Zero(), -1}, contacts),
               std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::collide
