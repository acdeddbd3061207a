// Tests of sim/tools/tool_contact_response.h: the reaction sums, the stiffness rule, damping
// without adhesion and bad input.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "contact_fixtures.h"
#include "sim/tools/tool_contact_response.h"

namespace incise::sim::tools {
namespace {

using contact_testing::ContactBlock;
using contact_testing::message_of;

// A 2 x 2 x 1 cm soft block with random node velocities, so that damping acts too.
ContactBlock moving_block() {
  ContactBlock block(Vec3(0.02, 0.02, 0.01), Vec3i(6, 6, 3), contact_testing::kSoft,
                     ContactBlock::Clamp::base);
  block.mesh.v = Points::Random(block.mesh.num_nodes(), 3) * 0.05;
  return block;
}

PenaltySettings settings_for(const ContactBlock& block) {
  PenaltySettings settings;
  settings.time_step = block.dt;
  return settings;
}

// Newton's third law and the moment balance: the node forces are the negated contact forces
// applied at the contact points, so their sum and their moment about the origin cancel the
// tool's exactly.
void expect_balanced(const ToolContactResponse& response, const Points& x,
                     const Points& node_forces) {
  const ToolReaction& reaction = response.reaction();
  ASSERT_GT(reaction.contacts, 3);
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero(), tool_moment = Vec3::Zero();
  for (int i = 0; i < x.rows(); ++i) {
    force += row3(node_forces, i);
    moment += row3(x, i).cross(row3(node_forces, i));
  }
  for (const ContactForce& c : response.contacts()) {
    tool_moment += c.contact.point.cross(c.force);
  }
  const Real scale = reaction.force.norm();
  EXPECT_LT((force + reaction.force).norm(), 1e-12 * scale);
  EXPECT_LT((moment + tool_moment).norm(), 1e-11 * scale * 0.03);
  // The reported torque is the moment of the tool's forces about its reference point.
  const Vec3 expected = tool_moment - reaction.reference.cross(reaction.force);
  EXPECT_LT((reaction.torque - expected).norm(), 1e-11 * scale * 0.03);
}

TEST(ContactResponse, SphereNodeForcesBalanceTheToolExactly) {
  ContactBlock block = moving_block();
  ToolContactResponse response(settings_for(block));
  Points node_forces = Points::Zero(block.mesh.num_nodes(), 3);
  // Off the grid, 1.5 mm deep into the top (z = 1 cm), moving down.
  const collide::Sphere tip{Vec3(0.0093, 0.0107, 0.0135), 0.005};
  response.apply(block.bvh, block.mesh.x, block.mesh.v, block.model->masses(), tip,
                 Vec3(0, 0, -0.1), node_forces);
  expect_balanced(response, block.mesh.x, node_forces);
  EXPECT_NEAR(response.reaction().max_depth, 0.0015, 1e-12);
  EXPECT_GT(response.reaction().force.z(), 0);  // pushed up, out of the tissue
}

TEST(ContactResponse, CapsuleNodeForcesBalanceTheToolExactly) {
  ContactBlock block = moving_block();
  ToolContactResponse response(settings_for(block));
  Points node_forces = Points::Zero(block.mesh.num_nodes(), 3);
  // A shaft lying slanted across the top, pressed in.
  const collide::Capsule shaft{Vec3(0.004, 0.006, 0.0118), Vec3(0.016, 0.013, 0.0122), 0.003};
  response.apply(block.bvh, block.mesh.x, block.mesh.v, block.model->masses(), shaft,
                 Vec3(0.02, 0, -0.05), node_forces);
  expect_balanced(response, block.mesh.x, node_forces);
}

TEST(ContactResponse, StiffnessAndDampingFollowTheMassRule) {
  ContactBlock block(Vec3(0.02, 0.02, 0.01), Vec3i(6, 6, 3), contact_testing::kSoft,
                     ContactBlock::Clamp::base);
  PenaltySettings settings = settings_for(block);
  settings.stiffness_fraction = 0.15;
  settings.damping_ratio = 0.3;
  ToolContactResponse response(settings);
  Points node_forces = Points::Zero(block.mesh.num_nodes(), 3);
  const collide::Sphere tip{Vec3(0.0093, 0.0107, 0.0135), 0.005};
  response.apply(block.bvh, block.mesh.x, block.mesh.v, block.model->masses(), tip, Vec3::Zero(),
                 node_forces);
  ASSERT_FALSE(response.contacts().empty());
  const VecX& m = block.model->masses();
  const Real dt = block.dt;
  for (const ContactForce& c : response.contacts()) {
    const Real mass = std::min({m[c.nodes[0]], m[c.nodes[1]], m[c.nodes[2]]});
    EXPECT_NEAR(c.stiffness, 0.15 * mass / (dt * dt), 1e-9 * c.stiffness);
    EXPECT_NEAR(c.damping, 2 * 0.3 * std::sqrt(0.15) * mass / dt, 1e-9 * c.damping);
    // At rest (tissue and tool still) only the elastic part acts: k depth n.
    EXPECT_LT((c.force - c.stiffness * c.contact.depth * c.contact.normal).norm(),
              1e-12 * c.force.norm());
    EXPECT_NEAR(c.contact.depth, tip.radius - (tip.centre - c.contact.point).norm(), 1e-15);
  }
}

// The stability bound of the rule: in mass-weighted coordinates the contacts' stiffness
// sum_c k_c (w_c w_c^T) (x) (n_c n_c^T) has its largest eigenvalue <= beta s / dt^2, s the most
// contacts at one node. Checked with the tip right above a surface node (s largest) and off it.
TEST(ContactResponse, ContactStiffnessStaysWithinTheStabilityBound) {
  ContactBlock block(Vec3(0.02, 0.02, 0.01), Vec3i(6, 6, 3), contact_testing::kSoft,
                     ContactBlock::Clamp::base);
  ToolContactResponse response(settings_for(block));
  Points node_forces = Points::Zero(block.mesh.num_nodes(), 3);
  const VecX& m = block.model->masses();
  const Real h = 0.02 / 6;
  for (const Vec3& centre :
       {Vec3(2 * h, 2 * h, 0.0135), Vec3(3 * h, 3 * h, 0.0140), Vec3(0.0093, 0.0107, 0.0135)}) {
    response.apply(block.bvh, block.mesh.x, block.mesh.v, m, collide::Sphere{centre, 0.005},
                   Vec3::Zero(), node_forces);
    const int n = block.mesh.num_nodes();
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    Eigen::VectorXi count = Eigen::VectorXi::Zero(n);
    for (const ContactForce& c : response.contacts()) {
      const Mat3 nn = c.contact.normal * c.contact.normal.transpose();
      for (int i = 0; i < 3; ++i) {
        ++count[c.nodes[i]];
        for (int j = 0; j < 3; ++j) {
          const Real wij = c.contact.barycentric[i] * c.contact.barycentric[j] /
                           std::sqrt(m[c.nodes[i]] * m[c.nodes[j]]);
          k.block<3, 3>(3 * c.nodes[i], 3 * c.nodes[j]) += c.stiffness * wij * nn;
        }
      }
    }
    const Real largest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k).eigenvalues().maxCoeff();
    const int s = count.maxCoeff();
    const Real beta = response.settings().stiffness_fraction;
    EXPECT_LE(largest * block.dt * block.dt, beta * s * (1 + 1e-12)) << "s = " << s;
    EXPECT_GE(s, 2);
  }
}

TEST(ContactResponse, DampingResistsApproachAndNeverPulls) {
  ContactBlock block(Vec3(0.02, 0.02, 0.01), Vec3i(6, 6, 3), contact_testing::kSoft,
                     ContactBlock::Clamp::base);
  ToolContactResponse response(settings_for(block));
  Points node_forces = Points::Zero(block.mesh.num_nodes(), 3);
  const collide::Sphere tip{Vec3(0.0093, 0.0107, 0.0145), 0.005};
  const VecX& m = block.model->masses();
  const Real still =
      response.apply(block.bvh, block.mesh.x, block.mesh.v, m, tip, Vec3::Zero(), node_forces)
          .force.z();
  const Real approaching =
      response.apply(block.bvh, block.mesh.x, block.mesh.v, m, tip, Vec3(0, 0, -0.05), node_forces)
          .force.z();
  EXPECT_GT(approaching, still);
  // Leaving fast: the damping would exceed the elastic part; the force is clamped at zero.
  response.apply(block.bvh, block.mesh.x, block.mesh.v, m, tip, Vec3(0, 0, 50), node_forces);
  for (const ContactForce& c : response.contacts()) {
    EXPECT_GE(c.force.dot(c.contact.normal), 0);
  }
  EXPECT_NEAR(response.reaction().force.norm(), 0, 1e-15);
}

TEST(ContactResponse, NoContactAddsNothing) {
  ContactBlock block(Vec3(0.02, 0.02, 0.01), Vec3i(4, 4, 2), contact_testing::kSoft,
                     ContactBlock::Clamp::base);
  ToolContactResponse response(settings_for(block));
  Points node_forces = Points::Zero(block.mesh.num_nodes(), 3);
  const ToolReaction& r =
      response.apply(block.bvh, block.mesh.x, block.mesh.v, block.model->masses(),
                     collide::Sphere{Vec3(0.01, 0.01, 0.0151), 0.005}, Vec3::Zero(), node_forces);
  EXPECT_EQ(r.contacts, 0);
  EXPECT_TRUE(node_forces.isZero(0));
}

TEST(ContactResponse, BadInputIsRefusedWithAPreciseMessage) {
  ContactBlock block(Vec3(0.02, 0.02, 0.01), Vec3i(2, 2, 1), contact_testing::kSoft,
                     ContactBlock::Clamp::base);
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_EQ(message_of([] { ToolContactResponse(PenaltySettings{}); }),
            "PenaltySettings: time_step must be finite and > 0, got 0.000000");
  EXPECT_NE(message_of([] {
              ToolContactResponse(PenaltySettings{1e-3, 1.5, 0.2});
            }).find("stiffness_fraction must be in (0, 1], got 1.5"),
            std::string::npos);
  EXPECT_NE(message_of([] {
              ToolContactResponse(PenaltySettings{1e-3, 0.1, -1});
            }).find("damping_ratio must be finite and >= 0"),
            std::string::npos);

  ToolContactResponse response(settings_for(block));
  Points f = Points::Zero(block.mesh.num_nodes(), 3);
  const VecX& m = block.model->masses();
  auto apply_sphere = [&](const collide::Sphere& s, const Vec3& u) {
    response.apply(block.bvh, block.mesh.x, block.mesh.v, m, s, u, f);
  };
  EXPECT_EQ(message_of([&] {
              apply_sphere({Vec3(0, 0, 0), -0.002}, Vec3::Zero());
            }),
            "ToolContactResponse::apply: tool radius must be finite and > 0, got -0.002000");
  EXPECT_EQ(message_of([&] {
              apply_sphere({Vec3(0, nan, 0), 0.002}, Vec3::Zero());
            }),
            "ToolContactResponse::apply: sphere centre must be finite, got (0, nan, 0)");
  EXPECT_EQ(message_of([&] {
              apply_sphere({Vec3(0, 0, 0), 0.002}, Vec3(nan, 0, 0));
            }),
            "ToolContactResponse::apply: tool_velocity must be finite, got (nan, 0, 0)");
  EXPECT_EQ(message_of([&] {
              response.apply(block.bvh, block.mesh.x, block.mesh.v, m,
                             collide::Capsule{Vec3::Zero(), Vec3(nan, 0, 0), 0.001}, Vec3::Zero(),
                             f);
            }),
            "ToolContactResponse::apply: capsule end b must be finite, got (nan, 0, 0)");
  Points short_forces = Points::Zero(3, 3);
  EXPECT_NE(message_of([&] {
              response.apply(block.bvh, block.mesh.x, block.mesh.v, m,
                             collide::Sphere{Vec3::Zero(), 0.001}, Vec3::Zero(), short_forces);
            }).find("node_forces 3"),
            std::string::npos);
}

}  // namespace
}  // namespace incise::sim::tools
