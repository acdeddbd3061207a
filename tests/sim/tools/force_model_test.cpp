// Tests of sim/tools/force_model.h: the exact contact stiffness against finite differences of the
// contact force (nodes held), the PSD projection.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <stdexcept>

#include "contact_fixtures.h"
#include "sim/tools/force_model.h"
#include "sim/tools/tool_contact_response.h"

namespace incise::sim::tools {
namespace {

using contact_testing::ContactBlock;

// A soft block whose surface is dented at random (up to 0.3 mm), so that the contacts' normals
// differ and the sphere meets faces, edges and vertices.
ContactBlock dented_block() {
  ContactBlock block(Vec3(0.02, 0.02, 0.01), Vec3i(6, 6, 3), contact_testing::kSoft,
                     ContactBlock::Clamp::base);
  std::srand(7);
  block.mesh.x += Points::Random(block.mesh.num_nodes(), 3) * 3e-4;
  block.bvh.refit(block.mesh.x);
  return block;
}

// The elastic contact force on the tool at the given shape, the nodes held still.
template <class Shape>
Vec3 contact_force(ContactBlock& block, ToolContactResponse& response, const Shape& shape) {
  Points f = Points::Zero(block.mesh.num_nodes(), 3);
  const Points still = Points::Zero(block.mesh.num_nodes(), 3);
  return response
      .apply(block.bvh, block.mesh.x, still, block.model->masses(), shape, Vec3::Zero(), f)
      .force;
}

collide::Sphere moved(const collide::Sphere& s, const Vec3& d) {
  return {s.centre + d, s.radius};
}
collide::Capsule moved(const collide::Capsule& s, const Vec3& d) {
  return {s.a + d, s.b + d, s.radius};
}

// -dF/dc by central differences, column by column.
template <class Shape>
Mat3 finite_difference_stiffness(ContactBlock& block, ToolContactResponse& response,
                                 const Shape& shape) {
  const Real h = 1e-8;
  Mat3 k;
  for (int a = 0; a < 3; ++a) {
    const Vec3 d = h * Vec3::Unit(a);
    k.col(a) = -(contact_force(block, response, moved(shape, d)) -
                 contact_force(block, response, moved(shape, -d))) /
               (2 * h);
  }
  return k;
}

void expect_symmetric_psd(const Mat3& k) {
  EXPECT_LT((k - k.transpose()).norm(), 1e-12 * k.norm());
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(k);
  EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-9 * k.norm());
}

TEST(ForceModel, SphereStiffnessMatchesFiniteDifferences) {
  ContactBlock block = dented_block();
  PenaltySettings settings;
  settings.time_step = block.dt;
  ToolContactResponse response(settings);
  int tangential = 0;
  for (const Vec3& centre : {Vec3(0.0093, 0.0107, 0.0135), Vec3(0.0101, 0.0099, 0.0146),
                             Vec3(0.0042, 0.0151, 0.0128), Vec3(0.0199, 0.0103, 0.0140)}) {
    const collide::Sphere tip{centre, 0.005};
    contact_force(block, response, tip);
    ASSERT_GT(response.contacts().size(), 2u);
    const std::vector<ContactForce> contacts = response.contacts();
    const Mat3 exact = exact_contact_stiffness(contacts, block.mesh.x, tip.radius);
    const Mat3 numeric = finite_difference_stiffness(block, response, tip);
    EXPECT_LT((exact - numeric).norm(), 1e-5 * exact.norm()) << "at " << centre.transpose() << "\n"
                                                             << exact << "\n"
                                                             << numeric;
    // The model: F0 the sum of the elastic forces, K the PSD part of the exact derivative.
    const LocalForceModel model = sphere_force_model(contacts, block.mesh.x, tip);
    Vec3 sum = Vec3::Zero();
    for (const ContactForce& c : contacts)
      sum += c.elastic_force;
    EXPECT_EQ(model.force, sum);
    EXPECT_EQ(model.reference_position, centre);
    expect_symmetric_psd(model.stiffness);
    EXPECT_LT((model.stiffness - positive_part(exact)).norm(), 1e-12 * exact.norm());
    const Eigen::SelfAdjointEigenSolver<Mat3> eigen(exact);
    if (eigen.eigenvalues().minCoeff() < 0) ++tangential;
  }
  // Some of these sit on edges or vertices of the dented surface, where the exact K has the
  // negative (rolling-off) directions that the projection removes.
  EXPECT_GT(tangential, 0);
}

TEST(ForceModel, CapsuleStiffnessMatchesFiniteDifferences) {
  ContactBlock block = dented_block();
  PenaltySettings settings;
  settings.time_step = block.dt;
  ToolContactResponse response(settings);
  const collide::Capsule shaft{Vec3(0.0041, 0.0063, 0.0121), Vec3(0.0157, 0.0128, 0.0124), 0.003};
  contact_force(block, response, shaft);
  ASSERT_GT(response.contacts().size(), 2u);
  const std::vector<ContactForce> contacts = response.contacts();
  const Mat3 exact = exact_contact_stiffness(contacts, block.mesh.x, shaft.radius, &shaft);
  const Mat3 numeric = finite_difference_stiffness(block, response, shaft);
  EXPECT_LT((exact - numeric).norm(), 1e-5 * exact.norm()) << exact << "\n" << numeric;
  expect_symmetric_psd(capsule_force_model(contacts, block.mesh.x, shaft).stiffness);
}

TEST(ForceModel, PositivePartIsTheNearestPsdMatrix) {
  Mat3 a;
  a << 2, 1, 0, 1, -3, 0.5, 0, 0.5, 1;
  const Mat3 p = positive_part(a);
  expect_symmetric_psd(p);
  // Same eigenvectors, negative eigenvalues dropped: a - p is negative semi-definite and
  // orthogonal to p (the Frobenius projection onto the PSD cone).
  const Eigen::SelfAdjointEigenSolver<Mat3> rest(a - p);
  EXPECT_LE(rest.eigenvalues().maxCoeff(), 1e-12);
  EXPECT_NEAR((p.transpose() * (a - p)).trace(), 0, 1e-12);
  const Mat3 psd = a.transpose() * a;
  EXPECT_LT((positive_part(psd) - psd).norm(), 1e-12 * psd.norm());
  Mat3 skewed = psd;
  skewed(0, 1) += 1;
  EXPECT_THROW(positive_part(skewed), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::tools
