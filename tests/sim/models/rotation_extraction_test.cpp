// polar_rotation (closed-form eigen path) against polar_rotation_svd (Jacobi SVD), on random
// deformation gradients: stretched, sheared, rotated, inverted, nearly flat and with repeated
// singular values; and the properties every result has (a proper rotation, R^T F symmetric).
#include <gtest/gtest.h>

#include <random>

#include "sim/models/rotation_extraction.h"

namespace incise::sim {
namespace {

Mat3 random_rotation(std::mt19937& random) {
  std::normal_distribution<Real> n(0, 1);
  Eigen::Quaternion<Real> q(n(random), n(random), n(random), n(random));
  return q.normalized().toRotationMatrix();
}

void expect_polar(const Mat3& f, const std::string& what) {
  SCOPED_TRACE(what);
  const Mat3 r = polar_rotation(f);
  EXPECT_LT((r.transpose() * r - Mat3::Identity()).norm(), 1e-12);
  EXPECT_NEAR(r.determinant(), 1, 1e-12);
  const Mat3 s = r.transpose() * f;
  // 1e-8: where two singular values agree to 1e-9 the closed-form eigenvectors lose digits.
  EXPECT_LT((s - s.transpose()).norm(), 1e-8 * (1 + f.norm()));
  EXPECT_LT((r - polar_rotation_svd(f)).norm(), 1e-8);
}

TEST(PolarRotation, MatchesTheSvdOnRandomDeformations) {
  std::mt19937 random(17);
  std::uniform_real_distribution<Real> stretch(0.2, 3);
  for (int k = 0; k < 2000; ++k) {
    const Mat3 u = random_rotation(random), v = random_rotation(random);
    Vec3 sigma(stretch(random), stretch(random), stretch(random));
    std::sort(sigma.data(), sigma.data() + 3, std::greater<>());
    if (k % 4 == 1) sigma(2) = -sigma(2);              // inverted
    if (k % 4 == 2) sigma(2) = 1e-4 * sigma(2);        // nearly flat
    if (k % 4 == 3) sigma(1) = sigma(0) * (1 + 1e-9);  // a repeated singular value
    expect_polar(u * sigma.asDiagonal() * v.transpose(), "case " + std::to_string(k));
  }
}

// Near a rotation (the Newton-Schulz path), also with small inversions mixed in (the eigen path).
TEST(PolarRotation, MatchesTheSvdNearRotations) {
  std::mt19937 random(29);
  std::uniform_real_distribution<Real> small(-0.04, 0.04);
  for (int k = 0; k < 2000; ++k) {
    Mat3 e;
    for (int i = 0; i < 9; ++i)
      e(i / 3, i % 3) = small(random);
    Mat3 f = random_rotation(random) * (Mat3::Identity() + e);
    if (k % 5 == 4) f.col(2) = -f.col(2);  // a reflection: inverted
    expect_polar(f, "near case " + std::to_string(k));
  }
}

TEST(PolarRotation, ExactForRotationsAndTheIdentity) {
  std::mt19937 random(3);
  EXPECT_LT((polar_rotation(Mat3::Identity()) - Mat3::Identity()).norm(), 1e-15);
  for (int k = 0; k < 100; ++k) {
    const Mat3 r = random_rotation(random);
    EXPECT_LT((polar_rotation(r) - r).norm(), 1e-12);
    EXPECT_LT((polar_rotation(2.5 * r) - r).norm(), 1e-12);
  }
}

TEST(PolarRotation, FlatAndZeroGradientsStillGiveARotation) {
  Mat3 line = Mat3::Zero();
  line(0, 0) = 1;  // every column on the x axis but one
  for (const Mat3& f : {Mat3(Mat3::Zero()), line}) {
    const Mat3 r = polar_rotation(f);
    EXPECT_LT((r.transpose() * r - Mat3::Identity()).norm(), 1e-12);
    EXPECT_NEAR(r.determinant(), 1, 1e-12);
  }
}

}  // namespace
}  // namespace incise::sim
