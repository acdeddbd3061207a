// SurfaceBvh contacts and sweeps against closed forms on flat sheets: a sphere and a capsule on
// a plane at known depth, a fast sphere crossing a thin sheet in one step.

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "collide_fixtures.h"
#include "sim/collide/surface_bvh.h"

namespace incise::sim::collide {
namespace {

const Contact& deepest(const std::vector<Contact>& contacts) {
  return *std::max_element(contacts.begin(), contacts.end(),
                           [](const Contact& a, const Contact& b) { return a.depth < b.depth; });
}

Vec3 on_triangle(const Points& points, const SurfaceBvh& bvh, const Contact& contact) {
  const Vec3i& t = bvh.triangle(contact.triangle);
  return contact.barycentric[0] * row3(points, t[0]) + contact.barycentric[1] * row3(points, t[1]) +
         contact.barycentric[2] * row3(points, t[2]);
}

class SheetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sheet_ = testing::flat_sheet(0.05, 20, 0);  // 10 cm square, 5 mm cells, normal +z
    bvh_.build(sheet_.points, sheet_.triangles);
  }
  testing::TestSurface sheet_;
  SurfaceBvh bvh_;
  std::vector<Contact> contacts_;
};

TEST_F(SheetTest, SphereOnThePlaneAtKnownDepth) {
  const Real r = 0.004, h = 0.0015;
  const Vec3 foot(0.0012, 0.0031, 0);  // inside a triangle, away from its edges
  bvh_.contacts(sheet_.points, Sphere{foot + Vec3(0, 0, h), r}, contacts_);
  ASSERT_FALSE(contacts_.empty());
  for (const Contact& contact : contacts_) {
    // Every touched triangle lies in the plane, so every closest point is at height 0 and no
    // deeper than the foot of the perpendicular.
    EXPECT_NEAR(contact.point.z(), 0, 1e-15);
    EXPECT_LE(contact.depth, r - h + 1e-15);
    EXPECT_TRUE(on_triangle(sheet_.points, bvh_, contact).isApprox(contact.point, 1e-12));
  }
  const Contact& best = deepest(contacts_);
  EXPECT_NEAR(best.depth, r - h, 1e-15);
  EXPECT_TRUE(best.normal.isApprox(Vec3::UnitZ(), 1e-12));
  EXPECT_TRUE(best.point.isApprox(foot, 1e-12));
}

TEST_F(SheetTest, SphereBehindTheSheetGetsNoContact) {
  // The rule of shape_triangle_contact.h: a centre on the inner side is not pulled through.
  bvh_.contacts(sheet_.points, Sphere{Vec3(0.001, 0.002, -0.001), 0.004}, contacts_);
  EXPECT_TRUE(contacts_.empty());
}

TEST_F(SheetTest, CapsuleOnThePlaneAtKnownDepth) {
  const Real r = 0.003;
  // Lying flat at height h: the triangles under the axis are r - h deep with normal +z; those
  // beside it or beyond its rounded ends are touched less deeply, at a slant.
  const Real h = 0.001;
  bvh_.contacts(sheet_.points, Capsule{Vec3(-0.01, 0.001, h), Vec3(0.012, 0.004, h), r}, contacts_);
  int under_axis = 0;
  for (const Contact& contact : contacts_) {
    EXPECT_LE(contact.depth, r - h + 1e-15);
    EXPECT_GE(contact.normal.z(), 0);
    if (std::abs(contact.depth - (r - h)) < 1e-15) {
      ++under_axis;
      EXPECT_TRUE(contact.normal.isApprox(Vec3::UnitZ(), 1e-12));
    }
  }
  // The axis runs over about 4.4 cells of 5 mm: at least two triangles per cell crossed.
  EXPECT_GE(under_axis, 8);
  // Tilted, its lower end at height h_a: the deepest contact is under that end.
  const Vec3 a(0.0021, -0.0013, 0.0005);
  bvh_.contacts(sheet_.points, Capsule{a, Vec3(0.02, 0.01, 0.03), r}, contacts_);
  ASSERT_FALSE(contacts_.empty());
  const Contact& best = deepest(contacts_);
  EXPECT_NEAR(best.depth, r - a.z(), 1e-15);
  EXPECT_TRUE(best.point.isApprox(Vec3(a.x(), a.y(), 0), 1e-12));
  EXPECT_TRUE(best.normal.isApprox(Vec3::UnitZ(), 1e-12));
  // Piercing the sheet, its lower end 1 mm below: it must move r + 1 mm along +z to clear.
  bvh_.contacts(sheet_.points,
                Capsule{Vec3(0.0021, -0.0013, -0.001), Vec3(0.0041, 0.0013, 0.02), r}, contacts_);
  const Contact& pierced = deepest(contacts_);
  EXPECT_NEAR(pierced.depth, r + 0.001, 1e-15);
  EXPECT_TRUE(pierced.normal.isApprox(Vec3::UnitZ(), 1e-12));
  EXPECT_NEAR(pierced.point.z(), 0, 1e-15);
}

TEST_F(SheetTest, FastSphereThroughTheSheetIsCaughtAtTheClosedFormTime) {
  // 0.5 m/s at a 1 kHz step would move 0.5 mm; this one jumps 10 cm in one step, through the
  // sheet, which a check at the end positions alone would miss.
  const Real r = 0.002, d0 = 0.05, d1 = -0.05;
  const Vec3 c0(0.0011, 0.0023, d0), c1(0.0031, -0.0017, d1);
  SweepHit hit;
  ASSERT_TRUE(bvh_.sweep(sheet_.points, Sphere{c0, r}, c1, hit));
  const Real t = (d0 - r) / (d0 - d1);
  EXPECT_NEAR(hit.time, t, 1e-14);
  EXPECT_TRUE(hit.normal.isApprox(Vec3::UnitZ(), 1e-12));
  EXPECT_TRUE(hit.point.isApprox((c0 + t * (c1 - c0)).cwiseProduct(Vec3(1, 1, 0)), 1e-12));
  // From below, the other side of the sheet.
  ASSERT_TRUE(bvh_.sweep(sheet_.points, Sphere{c1, r}, c0, hit));
  EXPECT_NEAR(hit.time, t, 1e-14);
  EXPECT_TRUE(hit.normal.isApprox(-Vec3::UnitZ(), 1e-12));
  // Beside the sheet: no hit.
  EXPECT_FALSE(bvh_.sweep(sheet_.points, Sphere{Vec3(0.06, 0, d0), r}, Vec3(0.06, 0, d1), hit));
}

TEST(SurfaceBvhSweep, ThinTwoLayerTissueStopsAtTheUpperLayer) {
  // Two sheets 0.5 mm apart (a thin membrane); a 1 mm sphere crossing both in one step hits
  // the upper one first.
  testing::TestSurface upper = testing::flat_sheet(0.02, 8, 0.0005);
  testing::TestSurface lower = testing::flat_sheet(0.02, 8, 0);
  testing::TestSurface both;
  both.points.resize(upper.points.rows() * 2, 3);
  both.points << upper.points, lower.points;
  both.triangles.resize(upper.triangles.rows() * 2, 3);
  both.triangles << upper.triangles,
      (lower.triangles.array() + static_cast<int>(upper.points.rows())).matrix();
  SurfaceBvh bvh;
  bvh.build(both.points, both.triangles);
  const Real r = 0.0005, d0 = 0.03, d1 = -0.03;
  SweepHit hit;
  ASSERT_TRUE(
      bvh.sweep(both.points, Sphere{Vec3(0.001, 0.001, d0), r}, Vec3(0.001, 0.001, d1), hit));
  EXPECT_LT(hit.triangle, upper.triangles.rows());
  EXPECT_NEAR(hit.time, (d0 - 0.0005 - r) / (d0 - d1), 1e-14);
}

}  // namespace
}  // namespace incise::sim::collide
