// The static surfaces around the tissue: an ellipsoid closed, outward and of the right volume;
// the liver's lie around the organ without cutting into it and enclose the laparoscope; the
// knee's bones are the scene's bones and its capsule encloses the soft tissue and the scope.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "sim/surgery/scene_presets.h"
#include "sim/surgery/surroundings.h"

namespace incise::sim::surgery {
namespace {

// The volume enclosed by outward triangles (divergence theorem).
Real enclosed_volume(const Surrounding& s) {
  Real volume = 0;
  for (Eigen::Index f = 0; f < s.triangles.rows(); ++f) {
    const Vec3 a = s.vertices.row(s.triangles(f, 0)), b = s.vertices.row(s.triangles(f, 1)),
               c = s.vertices.row(s.triangles(f, 2));
    volume += a.dot(b.cross(c)) / 6;
  }
  return volume;
}

// For an ellipsoid_surrounding: whether p lies inside (its centre and radii are its vertices'
// bounding box: the grid has the poles and, with even stacks and slices a multiple of 4, the
// equator's extreme points).
bool inside_ellipsoid(const Surrounding& s, const Vec3& p) {
  const Vec3 low = s.vertices.colwise().minCoeff().transpose();
  const Vec3 high = s.vertices.colwise().maxCoeff().transpose();
  return ((p - (low + high) / 2).cwiseQuotient((high - low) / 2)).squaredNorm() < 1;
}

const Surrounding& named(const std::vector<Surrounding>& all, const std::string& name) {
  for (const Surrounding& s : all)
    if (s.name == name) return s;
  throw std::out_of_range("no surrounding " + name);
}

TEST(Surroundings, AnEllipsoidIsClosedOutwardAndHoldsItsVolume) {
  const Vec3 radii(0.03, 0.02, 0.01);
  const Surrounding s =
      ellipsoid_surrounding("e", SurroundingKind::organ, Vec3(0.1, -0.2, 0.3), radii, 64, 32);
  // Every edge is shared by exactly two triangles, in opposite directions.
  std::map<std::pair<int, int>, int> directed;
  for (Eigen::Index f = 0; f < s.triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      ++directed[{s.triangles(f, k), s.triangles(f, (k + 1) % 3)}];
  for (const auto& [edge, n] : directed) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
  }
  // The inscribed polyhedron: a little less than the ellipsoid's 4/3 pi abc, positive (outward).
  const Real exact = 4.0 / 3.0 * std::numbers::pi * radii.prod();
  EXPECT_LT(enclosed_volume(s), exact);
  EXPECT_GT(enclosed_volume(s), 0.98 * exact);
  EXPECT_TRUE(inside_ellipsoid(s, Vec3(0.1, -0.2, 0.3) + 0.99 * Vec3(0.03, 0, 0)));
  EXPECT_THROW(ellipsoid_surrounding("e", SurroundingKind::organ, Vec3::Zero(), Vec3(1, 0, 1)),
               std::invalid_argument);
  EXPECT_THROW(ellipsoid_surrounding("e", SurroundingKind::organ, Vec3::Zero(), radii, 2, 8),
               std::invalid_argument);
}

TEST(Surroundings, TheLiversLieAroundTheOrganAndTheAbdominalWallEnclosesTheLaparoscope) {
  const SurgicalSceneSetup setup = make_liver_surgery(LiverSceneOptions{});
  const Points& rest = setup.spec.tissue.rest;
  const Vec3 low = rest.colwise().minCoeff().transpose();
  const Vec3 high = rest.colwise().maxCoeff().transpose();
  // The posterior wall is wholly below the organ's lowest point, and wider than the organ.
  const Surrounding& bed = named(setup.surroundings, "posterior wall");
  EXPECT_LT(bed.vertices.col(2).maxCoeff(), low.z());
  EXPECT_LT(bed.vertices.col(0).minCoeff(), low.x());
  EXPECT_GT(bed.vertices.col(0).maxCoeff(), high.x());
  // The wall encloses the organ and a scope 8 cm above and in front of the marked line, and is
  // hidden from a camera outside the body.
  const Surrounding& wall = named(setup.surroundings, "abdominal wall");
  EXPECT_TRUE(wall.inside_only);
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1) ? high.x() : low.x(), (corner & 2) ? high.y() : low.y(),
                 (corner & 4) ? high.z() : low.z());
    EXPECT_TRUE(inside_ellipsoid(wall, p)) << corner;
  }
  const Vec3 middle = 0.5 * (setup.cut_target.front() + setup.cut_target.back());
  EXPECT_TRUE(inside_ellipsoid(wall, middle + 0.08 * Vec3(0, -0.5, 0.8).normalized()));
  // The neighbours (the stomach beside the left lobe, the omentum in front) touch no part of
  // the organ, and show from outside too.
  for (const char* name : {"stomach", "omentum"}) {
    const Surrounding& s = named(setup.surroundings, name);
    EXPECT_FALSE(s.inside_only);
    int inside = 0;
    for (Eigen::Index n = 0; n < rest.rows(); ++n)
      inside += inside_ellipsoid(s, rest.row(n).transpose()) ? 1 : 0;
    EXPECT_EQ(inside, 0) << name;
  }
}

TEST(Surroundings, TheKneesBonesAreItsBonesAndTheCapsuleEnclosesTheJointAndTheScope) {
  const SurgicalSceneSetup setup = make_knee_surgery(KneeSceneOptions{});
  ASSERT_EQ(setup.surroundings.size(), setup.spec.bones.size() + 1);
  for (std::size_t b = 0; b < setup.spec.bones.size(); ++b) {
    EXPECT_EQ(setup.surroundings[b].kind, SurroundingKind::bone);
    EXPECT_EQ(setup.surroundings[b].vertices, setup.spec.bones[b].vertices);
    EXPECT_EQ(setup.surroundings[b].triangles, setup.spec.bones[b].triangles);
  }
  const Surrounding& capsule = named(setup.surroundings, "joint capsule");
  EXPECT_TRUE(capsule.inside_only);
  const Points& rest = setup.spec.tissue.rest;
  for (Eigen::Index n = 0; n < rest.rows(); ++n)
    ASSERT_TRUE(inside_ellipsoid(capsule, rest.row(n).transpose())) << n;
  for (const Portal& portal : setup.portals)
    EXPECT_TRUE(inside_ellipsoid(capsule, portal.position + 0.005 * portal.direction))
        << portal.name;
}

}  // namespace
}  // namespace incise::sim::surgery
