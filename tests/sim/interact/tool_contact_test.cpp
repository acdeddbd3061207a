#include "sim/interact/tool_contact.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "sim/mesh/box_mesher.h"

namespace incise::sim {
namespace {

constexpr SphereTool kTool{0.005, 300, 0};

// One free node, a surface of that node alone.
struct SingleNode {
  BoundarySurface surface{{0}, Triangles(0, 3), {}};
  Points x = Points::Zero(1, 3);
  Points f = Points::Zero(1, 3);
};

TEST(SphereContact, SingleNodeInsideIsPushedOutAlongTheRadius) {
  SingleNode node;
  node.x << 0.001, 0.002, -0.002;  // |x - c| = 3 mm
  const Vec3 centre = Vec3::Zero();
  const ToolContact contact = apply_sphere_contact(kTool, centre, node.surface, node.x, node.f);
  const Real depth = 0.002;
  const Vec3 n = Vec3(1, 2, -2) / 3;
  EXPECT_EQ(contact.nodes_in_contact, 1);
  EXPECT_NEAR(contact.max_depth, depth, 1e-17);
  EXPECT_LT((row3(node.f, 0) - kTool.stiffness * depth * n).norm(), 1e-15);
  EXPECT_LT((contact.force_on_tool + kTool.stiffness * depth * n).norm(), 1e-15);
  // Exact stiffness k (n n^T - (d / rho) (I - n n^T)); its PSD part keeps the normal term.
  const Mat3 normal = n * n.transpose();
  const Mat3 exact = kTool.stiffness * (normal - (depth / 0.003) * (Mat3::Identity() - normal));
  EXPECT_LT((contact.exact_stiffness - exact).norm(), 1e-10);
  EXPECT_LT((contact.stiffness - kTool.stiffness * normal).norm(), 1e-10);
}

TEST(SphereContact, NodesOnOrOutsideTheSphereAreUntouched) {
  SingleNode node;
  node.x << 0.005, 0, 0;  // on the sphere: depth 0
  ToolContact contact = apply_sphere_contact(kTool, Vec3::Zero(), node.surface, node.x, node.f);
  EXPECT_EQ(contact.nodes_in_contact, 0);
  EXPECT_TRUE(node.f.isZero(0));
  EXPECT_TRUE(contact.force_on_tool.isZero(0));
  EXPECT_TRUE(contact.stiffness.isZero(0));
  node.x << 0.1, 0.1, 0.1;
  contact = apply_sphere_contact(kTool, Vec3::Zero(), node.surface, node.x, node.f);
  EXPECT_EQ(contact.nodes_in_contact, 0);
  EXPECT_EQ(contact.max_depth, 0);
}

TEST(SphereContact, NodeAtTheCentreGetsAFiniteUpwardForce) {
  SingleNode node;
  node.x << 0.01, 0.02, 0.03;
  const Vec3 centre = row3(node.x, 0);
  const ToolContact contact = apply_sphere_contact(kTool, centre, node.surface, node.x, node.f);
  ASSERT_TRUE(node.f.allFinite());
  ASSERT_TRUE(contact.exact_stiffness.allFinite());
  EXPECT_LT((row3(node.f, 0) - kTool.stiffness * kTool.radius * Vec3::UnitZ()).norm(), 1e-15);
  EXPECT_NEAR(contact.max_depth, kTool.radius, 0);
}

// A box of tissue whose top face the tool presses into at a generic point, several nodes inside.
struct Pressed {
  TetMesh mesh = make_box_mesh(Vec3(0.04, 0.04, 0.02), Vec3i(8, 8, 4));
  BoundarySurface surface = boundary_surface(mesh);
  Vec3 centre = Vec3(0.0213, 0.0187, 0.02 + 0.0051 - 0.0037);
  Points f = Points::Zero(mesh.num_nodes(), 3);
};

ToolContact press(Pressed& pressed, const Vec3& centre) {
  pressed.f.setZero();
  return apply_sphere_contact(kTool, centre, pressed.surface, pressed.mesh.x, pressed.f);
}

TEST(SphereContact, ExactStiffnessIsMinusTheDerivativeOfTheToolForce) {
  Pressed pressed;
  // Nodes at several depths and directions, none within a step of the sphere.
  const ToolContact contact = press(pressed, pressed.centre);
  ASSERT_GE(contact.nodes_in_contact, 3);
  const Real h = 1e-7;  // [m]; central differences: error O(h^2) on a smooth force
  Mat3 numeric;
  for (int j = 0; j < 3; ++j) {
    const Vec3 step = h * Vec3::Unit(j);
    const ToolContact plus = press(pressed, pressed.centre + step);
    const ToolContact minus = press(pressed, pressed.centre - step);
    ASSERT_EQ(plus.nodes_in_contact, contact.nodes_in_contact);
    ASSERT_EQ(minus.nodes_in_contact, contact.nodes_in_contact);
    numeric.col(j) = -(plus.force_on_tool - minus.force_on_tool) / (2 * h);
  }
  EXPECT_LT((contact.exact_stiffness - numeric).norm(), 1e-5 * contact.exact_stiffness.norm())
      << "exact\n"
      << contact.exact_stiffness << "\nnumeric\n"
      << numeric;
  EXPECT_LT((contact.exact_stiffness - contact.exact_stiffness.transpose()).norm(), 1e-12);
}

TEST(SphereContact, StiffnessIsThePositiveSemiDefinitePartOfTheExactOne) {
  Pressed pressed;
  for (const Real dz : {-0.002, 0.0, 0.002}) {
    const ToolContact contact = press(pressed, pressed.centre + Vec3(0, 0, dz));
    ASSERT_GT(contact.nodes_in_contact, 0);
    const Mat3& K = contact.stiffness;
    EXPECT_LT((K - K.transpose()).norm(), 1e-12);
    const Eigen::SelfAdjointEigenSolver<Mat3> eigen(K);
    const Real scale = kTool.stiffness * contact.nodes_in_contact;
    EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-12 * scale);
    EXPECT_LE(eigen.eigenvalues().maxCoeff(), scale * (1 + 1e-12));
    // It agrees with the exact stiffness wherever that is PSD: on its own eigenvectors with
    // non-negative eigenvalues, and is 0 on the others.
    const Eigen::SelfAdjointEigenSolver<Mat3> exact(contact.exact_stiffness);
    for (int e = 0; e < 3; ++e) {
      const Vec3 u = exact.eigenvectors().col(e);
      const Real expected = std::max(exact.eigenvalues()(e), 0.0);
      EXPECT_NEAR(u.dot(K * u), expected, 1e-9 * scale);
    }
  }
}

TEST(SphereContact, NodeForcesAndToolReactionCancel) {
  Pressed pressed;
  Points v = Points::Random(pressed.mesh.num_nodes(), 3) * 0.1;
  const SphereTool damped{kTool.radius, kTool.stiffness, 0.4};
  pressed.f.setConstant(0.25);  // contact forces are added to what is there
  const ToolContact contact = apply_sphere_contact(damped, pressed.centre, Vec3(0.05, -0.02, 0.1),
                                                   pressed.surface, pressed.mesh.x, v, pressed.f);
  ASSERT_GT(contact.nodes_in_contact, 0);
  const Vec3 on_nodes = (pressed.f.array() - 0.25).matrix().colwise().sum().transpose();
  EXPECT_LT((on_nodes + contact.force_on_tool).norm(), 1e-15);
  // Only nodes inside the sphere are touched.
  int touched = 0;
  for (int i = 0; i < pressed.mesh.num_nodes(); ++i) {
    if ((pressed.f.row(i).array() != 0.25).any()) {
      ++touched;
      EXPECT_LT((row3(pressed.mesh.x, i) - pressed.centre).norm(), kTool.radius);
    }
  }
  EXPECT_EQ(touched, contact.nodes_in_contact);
}

TEST(SphereContact, DampingOpposesTheNormalRelativeVelocity) {
  SingleNode node;
  node.x << 0, 0, -0.003;  // below the centre: n = -z, depth 2 mm
  const SphereTool damped{kTool.radius, kTool.stiffness, 0.5};
  Points v(1, 3);
  v << 0.7, 0, 0.2;  // moving up into the tool (tangential part is not damped)
  const Vec3 u(0, 0, -0.1);
  const ToolContact contact =
      apply_sphere_contact(damped, Vec3::Zero(), u, node.surface, node.x, v, node.f);
  const Vec3 expected = Vec3(0, 0, -kTool.stiffness * 0.002 - 0.5 * 0.3);
  EXPECT_LT((row3(node.f, 0) - expected).norm(), 1e-15);
  EXPECT_LT((contact.force_on_tool + expected).norm(), 1e-15);
}

}  // namespace
}  // namespace incise::sim
