#include "sim/remesh/predicates.h"

#include <array>
#include <random>

#include <gtest/gtest.h>

#include "sim/mesh/tet_mesh.h"

namespace incise::sim::remesh {
namespace {

TEST(RemeshPredicates, OrientationAgreesWithSignedVolume) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> coord(-1, 1);
  for (int i = 0; i < 200; ++i) {
    const Vec3 a(coord(rng), coord(rng), coord(rng)), b(coord(rng), coord(rng), coord(rng)),
        c(coord(rng), coord(rng), coord(rng)), d(coord(rng), coord(rng), coord(rng));
    const Real v = signed_volume(a, b, c, d);
    if (std::abs(v) < 1e-9) continue;
    EXPECT_EQ(orientation(a, b, c, d), v > 0 ? 1 : -1);
    EXPECT_EQ(orientation(a, c, b, d), v > 0 ? -1 : 1);
  }
  EXPECT_EQ(orientation(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, 0.7, 0)), 0);
}

TEST(RemeshPredicates, SideOfSphereOfTheUnitTet) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);  // circumcentre (1/2, 1/2, 1/2)
  ASSERT_EQ(orientation(a, b, c, d), 1);
  EXPECT_EQ(side_of_sphere(a, b, c, d, Vec3(0.5, 0.5, 0.5)), 1);
  EXPECT_EQ(side_of_sphere(a, b, c, d, Vec3(2, 2, 2)), -1);
  EXPECT_EQ(side_of_sphere(a, b, c, d, Vec3(1, 1, 1)), 0);  // the cube corner is on it
}

// The eight corners of the unit cube are cospherical: every in-sphere test among them is a tie
// that the perturbation must break consistently. For a face (a, b, c) with d and e on opposite
// sides, "e inside the sphere of abcd" and "d inside the sphere of abce" are the same
// statement (the face is not locally Delaunay), perturbed or not.
TEST(RemeshPredicates, PerturbedInSphereBreaksCubeTiesSymmetrically) {
  std::array<Vec3, 8> corner;
  for (int i = 0; i < 8; ++i)
    corner[i] = Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  int checked = 0;
  for (int a = 0; a < 8; ++a) {
    for (int b = 0; b < 8; ++b) {
      for (int c = 0; c < 8; ++c) {
        for (int d = 0; d < 8; ++d) {
          for (int e = 0; e < 8; ++e) {
            if (a == b || a == c || a == d || a == e || b == c || b == d || b == e || c == d ||
                c == e || d == e) {
              continue;
            }
            const Vec3 &pa = corner[a], &pb = corner[b], &pc = corner[c];
            if (orientation(pa, pb, pc, corner[d]) != 1 ||
                orientation(pa, pb, pc, corner[e]) != -1) {
              continue;
            }
            const int e_in =
                side_of_sphere_perturbed(pa, pb, pc, corner[d], corner[e], a, b, c, d, e);
            // (a, c, b, e) is positively oriented since e is below abc.
            const int d_in =
                side_of_sphere_perturbed(pa, pc, pb, corner[e], corner[d], a, c, b, e, d);
            ASSERT_NE(e_in, 0);
            EXPECT_EQ(e_in, d_in) << a << b << c << d << e;
            ++checked;
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(RemeshPredicates, PerturbationDoesNotChangeAStrictAnswer) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);
  EXPECT_EQ(side_of_sphere_perturbed(a, b, c, d, Vec3(0.5, 0.5, 0.5), 0, 1, 2, 3, 4), 1);
  EXPECT_EQ(side_of_sphere_perturbed(a, b, c, d, Vec3(2, 2, 2), 4, 1, 2, 3, 0), -1);
}

}  // namespace
}  // namespace incise::sim::remesh
