// The strain kernel of the damage metrics (sim/tools/damage_strain.h) against closed forms: a
// uniaxial stretch, a simple shear, a rigid motion (no strain), a pure compression (no positive
// principal strain), on a skewed tet so that Dm^-1 is not trivial.

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

#include "sim/tools/damage_strain.h"

namespace incise::sim::tools {
namespace {

// A skewed, positively oriented rest tet [m].
const Vec3 kRest[4] = {Vec3(0.01, -0.02, 0.003), Vec3(0.05, -0.01, 0.0), Vec3(0.02, 0.03, 0.01),
                       Vec3(0.015, 0.0, 0.045)};

Real strain_under(const Mat3& f, const Vec3& translation = Vec3::Zero()) {
  Mat3 inverse;
  EXPECT_GT(rest_edge_inverse(kRest[0], kRest[1], kRest[2], kRest[3], inverse), 0);
  Vec3 x[4];
  for (int k = 0; k < 4; ++k)
    x[k] = f * kRest[k] + translation;
  return max_principal_green_strain(x[0], x[1], x[2], x[3], inverse);
}

// The trigonometry-free largest eigenvalue against Eigen's iterative solver: random symmetric
// matrices, and ones with two or three equal eigenvalues (r = -1, r = 1 and the multiple of I,
// where Newton starts at or converges to a double or triple root). Like every closed form from
// the invariants (Eigen's computeDirect too), it loses half the digits where the two largest
// eigenvalues nearly coincide (1 + r carries round-off, its square root sets t): the bound is
// sqrt(machine epsilon) of the matrix's size there and round-off elsewhere.
TEST(DamageStrain, LargestEigenvalueEqualsTheIterativeSolversToRoundOff) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<Real> u(-1, 1);
  Real worst_separated = 0, worst = 0;
  const auto check = [&](const Mat3& a) {
    Eigen::SelfAdjointEigenSolver<Mat3> reference(a, Eigen::EigenvaluesOnly);
    const Vec3 eigenvalues = reference.eigenvalues();
    const Real error = std::abs(largest_symmetric_eigenvalue(a) - eigenvalues(2)) / (1 + a.norm());
    worst = std::max(worst, error);
    const bool separated = eigenvalues(2) - eigenvalues(1) > 1e-3 * (1 + a.norm());
    if (separated) worst_separated = std::max(worst_separated, error);
    EXPECT_LT(error, separated ? 1e-13 : 3e-8) << a;
  };
  for (int n = 0; n < 2000; ++n) {
    Mat3 m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        m(i, j) = u(rng);
    check(0.5 * (m + m.transpose()));
    // A deformation's C = F^T F near I, as the damage tracker meets it.
    const Mat3 f = Mat3::Identity() + 0.01 * u(rng) * m;
    check(f.transpose() * f);
    // Repeated eigenvalues in a random frame.
    const Mat3 q =
        Eigen::Quaternion<Real>(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    const Real a = u(rng), b = u(rng);
    check(q * Vec3(a, a, b).asDiagonal() * q.transpose());
    check(q * Vec3(a, b, b).asDiagonal() * q.transpose());
    check(q * Vec3(a, a, a).asDiagonal() * q.transpose());
  }
  EXPECT_TRUE(std::isnan(largest_symmetric_eigenvalue(Mat3::Constant(std::nan("")))));
  // Far from 1 in size, where the deviator's cube would underflow or overflow: still its
  // largest eigenvalue, relative to the size.
  Mat3 nearly_i = Mat3::Identity();
  nearly_i(0, 1) = nearly_i(1, 0) = 1e-120;
  EXPECT_EQ(largest_symmetric_eigenvalue(nearly_i), 1);
  const Mat3 shape = (Mat3() << 2, 1, 0, 1, 3, -1, 0, -1, 1).finished();
  const Real expected = Eigen::SelfAdjointEigenSolver<Mat3>(shape).eigenvalues()(2);
  for (const Real scale : {1e-150, 1e-110, 1e110, 1e150}) {
    EXPECT_NEAR(largest_symmetric_eigenvalue(scale * shape) / scale, expected, 1e-13 * expected)
        << scale;
  }
  std::printf("largest relative error %.2g (%.2g with the two largest eigenvalues apart)\n", worst,
              worst_separated);
}

TEST(DamageStrain, UniaxialStretchGivesHalfOfStretchSquaredMinusOne) {
  for (const Real l : {1.05, 1.1, 1.5, 2.0}) {
    const Mat3 f = Vec3(1, l, 1).asDiagonal();
    EXPECT_NEAR(strain_under(f), (l * l - 1) / 2, 1e-12) << "stretch " << l;
  }
}

TEST(DamageStrain, SimpleShearGivesTheLargestEigenvalueOfItsGreenStrain) {
  // F = I + g e_x e_y^T: the x-y block of C = F^T F is [[1, g], [g, 1 + g^2]] with trace 2 + g^2
  // and determinant 1, so its larger eigenvalue is (2 + g^2 + g sqrt(g^2 + 4)) / 2.
  for (const Real g : {0.1, 0.3, 1.0}) {
    Mat3 f = Mat3::Identity();
    f(0, 1) = g;
    const Real c_max = (2 + g * g + g * std::sqrt(g * g + 4)) / 2;
    EXPECT_NEAR(strain_under(f), (c_max - 1) / 2, 1e-12) << "shear " << g;
  }
}

TEST(DamageStrain, RigidMotionGivesNoStrain) {
  const Mat3 r = Eigen::AngleAxisd(1.2, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  EXPECT_NEAR(strain_under(r, Vec3(0.3, -1, 2)), 0, 1e-13);
}

TEST(DamageStrain, CompressionAloneGivesNoPositivePrincipalStrain) {
  // Principal strains (0.8^2 - 1) / 2 along z and 0 along x and y: the largest is 0.
  EXPECT_NEAR(strain_under(Vec3(1, 1, 0.8).asDiagonal()), 0, 1e-13);
  // An inverted tet (a reflection with stretch 1.2) still has the strain of its stretch.
  EXPECT_NEAR(strain_under(Vec3(-1.2, 1, 1).asDiagonal()), (1.44 - 1) / 2, 1e-12);
}

TEST(DamageStrain, FlatRestTetIsReported) {
  Mat3 inverse = Mat3::Constant(7);
  EXPECT_EQ(rest_edge_inverse(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), inverse),
            0);
  EXPECT_EQ(inverse, Mat3::Constant(7));
  EXPECT_LT(rest_edge_inverse(Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), inverse),
            0);
}

TEST(DamageStrain, NanPositionsGiveNan) {
  Mat3 inverse;
  rest_edge_inverse(kRest[0], kRest[1], kRest[2], kRest[3], inverse);
  const Vec3 bad(std::nan(""), 0, 0);
  EXPECT_TRUE(std::isnan(max_principal_green_strain(bad, kRest[1], kRest[2], kRest[3], inverse)));
}

// The four-lane kernel against the scalar one, slot by slot. Each slot is a random rest tet of its
// own under its own deformation, from a seeded generator: random ones near the identity and, in
// turn, an inversion (a reflection), a flattening (F of rank 2), a scaled rotation (C a multiple
// of I: the mean branch), a uniaxial stretch and an equal stretch along two axes (C with two equal
// largest eigenvalues: the double root). Untracked slots get 0 and read no node (theirs lie past
// the end of x); the count is not a multiple of four; a NaN position gives NaN in its slot only.
TEST(DamageStrain, FourLaneKernelEqualsTheScalarOneSlotBySlot) {
  std::mt19937 random(11);
  std::uniform_real_distribution<Real> unit(-1, 1);
  const auto random_matrix = [&] {
    Mat3 m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        m(i, j) = unit(random);
    return m;
  };
  const int slots = 47;
  Points rest(4 * slots, 3), x(4 * slots, 3);
  Tets tets(slots, 4);
  std::vector<Mat3> inverse(slots);
  std::vector<char> tracked(slots, 1);
  for (int s = 0; s < slots; ++s) {
    for (;;) {
      const Vec3 centre = 0.05 * Vec3(unit(random), unit(random), unit(random));
      for (int k = 0; k < 4; ++k) {
        tets(s, k) = 4 * s + k;
        rest.row(4 * s + k) =
            (centre + 0.01 * Vec3(unit(random), unit(random), unit(random))).transpose();
      }
      if (rest_edge_inverse(row3(rest, 4 * s), row3(rest, 4 * s + 1), row3(rest, 4 * s + 2),
                            row3(rest, 4 * s + 3), inverse[static_cast<std::size_t>(s)]) > 1e-8)
        break;
    }
    const Mat3 rotation =
        Eigen::Quaterniond(Eigen::Vector4d(unit(random), unit(random), unit(random), unit(random)))
            .normalized()
            .toRotationMatrix();
    Mat3 f = Mat3::Identity() + 0.5 * random_matrix();
    switch (s % 6) {
      case 1:
        f = rotation * Vec3(1.2, 0.9, -1.1).asDiagonal();
        break;  // inverted
      case 2:
        f = rotation * Vec3(1.3, 0.8, 0.0).asDiagonal();
        break;  // flattened
      case 3:
        f = 1.7 * rotation;
        break;  // C = 2.89 I
      case 4:
        f = rotation * Vec3(2.5, 1.0, 1.0).asDiagonal();
        break;  // uniaxial
      case 5:
        f = rotation * Vec3(1.6, 1.6, 0.7).asDiagonal();
        break;  // double largest
      default:
        break;
    }
    const Vec3 shift(unit(random), unit(random), unit(random));
    for (int k = 0; k < 4; ++k)
      x.row(4 * s + k) = (f * row3(rest, 4 * s + k) + shift).transpose();
  }
  tracked[7] = tracked[20] = tracked[46] = 0;
  tets(20, 0) = tets(46, 3) = 1000000;  // untracked: never read
  std::vector<Real> strain(slots, -1);
  max_principal_green_strains(slots, tets.data(), x.data(), inverse.data(), tracked.data(),
                              strain.data());
  for (int s = 0; s < slots; ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (!tracked[i]) {
      EXPECT_EQ(strain[i], 0) << "slot " << s;
      continue;
    }
    const Real expected =
        max_principal_green_strain(row3(x, tets(s, 0)), row3(x, tets(s, 1)), row3(x, tets(s, 2)),
                                   row3(x, tets(s, 3)), inverse[i]);
    // Round-off, and where the two largest eigenvalues coincide the closed form's half digits
    // (the test above).
    const Real tolerance = s % 6 == 5 || s % 6 == 3 ? 1e-7 : 1e-12;
    EXPECT_NEAR(strain[i], expected, tolerance * (1 + std::abs(expected))) << "slot " << s;
  }
  // The closed forms of the special deformations: (s^2 - 1) / 2 with s the largest stretch.
  EXPECT_NEAR(strain[3], (1.7 * 1.7 - 1) / 2, 1e-7);
  EXPECT_NEAR(strain[4], (2.5 * 2.5 - 1) / 2, 1e-12);
  EXPECT_NEAR(strain[5], (1.6 * 1.6 - 1) / 2, 1e-7);
  EXPECT_NEAR(strain[1], (1.2 * 1.2 - 1) / 2, 1e-12);
  const int bad = tets(5, 2);
  x(bad, 0) = std::nan("");
  max_principal_green_strains(slots, tets.data(), x.data(), inverse.data(), tracked.data(),
                              strain.data());
  for (int s = 0; s < slots; ++s) {
    const auto i = static_cast<std::size_t>(s);
    EXPECT_EQ(std::isnan(strain[i]), s == 5) << "slot " << s;
  }
}

}  // namespace
}  // namespace incise::sim::tools
