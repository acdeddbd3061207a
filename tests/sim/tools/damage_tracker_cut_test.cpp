// DamageTracker's cut part (sim/tools/damage_tracker.h) with real cuts (sim/cut/cut_mesh.h) of a
// box whose marked line runs along x on its top face at y = 0.015, with the target surface
// straight down from it: closed forms for a cut on the line, offset from it by d, and tilted
// about it by an angle, and the never event when a protected label is cut.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "sim/cut/cut_mesh.h"
#include "sim/mesh/box_mesher.h"
#include "sim/tools/damage_tracker.h"

namespace incise::sim::tools {
namespace {

constexpr Real kLx = 0.06, kLy = 0.03, kLz = 0.02;  // [m] box, cells of 0.01
constexpr Real kLineY = 0.015;                      // [m] the marked line, mid-cell
constexpr Real kHalfWidth = 0.002;                  // [m]
// A snap this small keeps every crossing where the plane puts it, so that crack faces lie on
// the cut plane to rounding (the default 5% would move some onto nearby nodes).
constexpr cut::CutOptions kExact{1e-6};

MarkedTarget marked_line() {
  MarkedTarget target;
  target.line.resize(3, 3);
  target.line << -0.01, kLineY, kLz, 0.03, kLineY, kLz, 0.07, kLineY, kLz;  // beyond the box
  target.depth_direction = Vec3(0, 0, -2);  // normalised by the tracker
  target.depth = 0.03;                      // below the box's bottom
  target.half_width = kHalfWidth;
  return target;
}

struct CutBox {
  TetMesh mesh = make_box_mesh(Vec3(kLx, kLy, kLz), Vec3i(6, 3, 2));
  DamageTracker tracker;

  explicit CutBox(DamageSettings settings, const Eigen::VectorXi& labels = {})
      : tracker(labelled(mesh, labels), std::move(settings)) {}

  static const TetMesh& labelled(TetMesh& mesh, const Eigen::VectorXi& labels) {
    if (labels.size() > 0) mesh.labels = labels;
    return mesh;
  }

  // Cuts along the plane through point with the unit in-plane directions u (along x) and w, the
  // blade far larger than the box, and reports it to the tracker.
  CutDamage cut(const Vec3& point, const Vec3& w) {
    const Vec3 u = Vec3::UnitX();
    const Tets old_tets = mesh.tets;
    const std::vector<char> old_alive(static_cast<std::size_t>(mesh.num_tets()), 1);
    const cut::CutReport report = cut::cut_mesh(
        mesh, cut::blade_sweep(point - u - w, point + u - w, point - u + w, point + u + w), kExact);
    EXPECT_GT(report.crack_faces.rows(), 0);
    std::vector<int> parents;
    parents_by_rest_centroid(mesh.rest, old_tets, old_alive, mesh.tets, report.changed_tets,
                             parents);
    tracker.update_elements(mesh, std::vector<char>(static_cast<std::size_t>(mesh.num_tets()), 1),
                            report.changed_tets, parents);
    return tracker.record_cut(mesh.rest, report.crack_faces);
  }
};

DamageSettings with_target() {
  DamageSettings settings;
  settings.target = marked_line();
  return settings;
}

TEST(DamageCut, CutOnTheMarkedLineIsAllOnTarget) {
  CutBox box(with_target());
  const CutDamage cut = box.cut(Vec3(0.03, kLineY, 0.01), Vec3::UnitZ());
  EXPECT_NEAR(cut.area, kLx * kLz, 1e-15);
  EXPECT_NEAR(cut.area_inside_target, kLx * kLz, 1e-15);
  EXPECT_EQ(cut.area_outside_target, 0);
  EXPECT_NEAR(cut.mean_distance, 0, 1e-15);
  EXPECT_NEAR(cut.max_distance, 0, 1e-15);
  EXPECT_FALSE(cut.never_event);
  const DamageMetrics m = box.tracker.metrics();
  EXPECT_EQ(m.cut_events, 1);
  EXPECT_NEAR(m.cut_area, kLx * kLz, 1e-15);
  EXPECT_EQ(m.cut_area_outside_target, 0);
  EXPECT_NEAR(m.cut_mean_distance, 0, 1e-15);
}

TEST(DamageCut, OffsetCutHasTheOffsetAsDistance) {
  // d inside the band: all on target; d outside: all off target. Every crack face is at d.
  for (const Real d : {0.001, -0.0015, 0.004}) {
    CutBox box(with_target());
    const CutDamage cut = box.cut(Vec3(0.03, kLineY + d, 0.01), Vec3::UnitZ());
    const Real outside = std::abs(d) > kHalfWidth ? kLx * kLz : 0;
    EXPECT_NEAR(cut.area, kLx * kLz, 1e-15) << "d = " << d;
    EXPECT_NEAR(cut.area_outside_target, outside, 1e-15) << "d = " << d;
    EXPECT_NEAR(cut.area_inside_target, kLx * kLz - outside, 1e-15) << "d = " << d;
    EXPECT_NEAR(cut.mean_distance, std::abs(d), 1e-12) << "d = " << d;
    EXPECT_NEAR(cut.max_distance, std::abs(d), 1e-12) << "d = " << d;
    EXPECT_NEAR(box.tracker.metrics().cut_area_outside_target, outside, 1e-15);
  }
}

TEST(DamageCut, TiltedCutHasTheClosedFormMeanDistance) {
  // The plane through the line tilted by a about it: a point s down the plane is s sin(a) from
  // the target, linear over every crack face, so the area-weighted mean of the centroids'
  // distances is exactly the mean over the cut, sin(a) (kLz / cos(a)) / 2 = kLz tan(a) / 2.
  // With tan(a) = 0.2 the band's edge (distance kHalfWidth) is at depth 0.01, the boundary
  // between the two cell layers: every crack face lies in one layer, so classifying faces by
  // their centroids is exact here, and the lower layer's cut, kLx (kLz / 2) / cos(a), is off
  // target.
  const Real a = std::atan(0.2);
  CutBox box(with_target());
  const Vec3 w(0, std::sin(a), -std::cos(a));
  const CutDamage cut = box.cut(Vec3(0.03, kLineY, kLz), w);
  const Real slant = kLz / std::cos(a);
  EXPECT_NEAR(cut.area, kLx * slant, 1e-15);
  EXPECT_NEAR(cut.mean_distance, kLz * std::tan(a) / 2, 1e-12);
  EXPECT_LE(cut.max_distance, kLz * std::tan(a) + 1e-12);
  EXPECT_GT(cut.max_distance, kLz * std::tan(a) / 2);
  EXPECT_NEAR(cut.area_outside_target, kLx * slant / 2, 1e-15);
  EXPECT_NEAR(cut.area_inside_target, kLx * slant / 2, 1e-15);
}

TEST(DamageCut, WithoutATargetEveryCutIsOffTarget) {
  CutBox box{DamageSettings{}};
  const CutDamage cut = box.cut(Vec3(0.03, kLineY, 0.01), Vec3::UnitZ());
  EXPECT_NEAR(cut.area_outside_target, kLx * kLz, 1e-15);
  EXPECT_EQ(cut.mean_distance, 0);
  EXPECT_EQ(box.tracker.metrics().cut_mean_distance, 0);
}

// The box with label 3 (protected) on the cells of y > 0.02.
CutBox protected_band_box() {
  const TetMesh mesh = CutBox{DamageSettings{}}.mesh;
  Eigen::VectorXi labels(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Real cy = 0;
    for (int k = 0; k < 4; ++k)
      cy += mesh.rest(mesh.tets(t, k), 1) / 4;
    labels(t) = cy > 0.02 ? 3 : 0;
  }
  DamageSettings settings = with_target();
  settings.protected_labels = {3};
  return CutBox(settings, labels);
}

TEST(DamageCut, CuttingAProtectedLabelIsANeverEvent) {
  // Label 3 (protected) on the cells of y > 0.02: the cut at y = 0.015 misses it, the one at
  // y = 0.025 runs through it over its whole cross-section.
  CutBox box = protected_band_box();

  const CutDamage first = box.cut(Vec3(0.03, kLineY, 0.01), Vec3::UnitZ());
  EXPECT_FALSE(first.never_event);
  EXPECT_EQ(first.protected_area, 0);
  EXPECT_FALSE(box.tracker.metrics().never_event);

  const CutDamage second = box.cut(Vec3(0.03, 0.025, 0.01), Vec3::UnitZ());
  EXPECT_TRUE(second.never_event);
  EXPECT_NEAR(second.protected_area, kLx * kLz, 1e-15);
  const DamageMetrics m = box.tracker.metrics();
  EXPECT_TRUE(m.never_event);
  EXPECT_EQ(m.cut_events, 2);
  EXPECT_NEAR(m.cut_area, 2 * kLx * kLz, 1e-15);
  EXPECT_NEAR(m.protected_cut_area, kLx * kLz, 1e-15);
  EXPECT_NEAR(m.cut_area_outside_target, kLx * kLz, 1e-15);
  EXPECT_NEAR(m.cut_mean_distance, 0.01 / 2, 1e-12);  // (0 + 0.01) / 2, equal areas
  EXPECT_NEAR(m.cut_max_distance, 0.01, 1e-12);
}

// Faces given with their labels (a progressive cut's, which the blade's temporary pieces may
// have split) count as the same faces found through their tets.
TEST(DamageCut, LabelledFacesCountAsTheirTetsSay) {
  CutBox box = protected_band_box();
  const Vec3 u = Vec3::UnitX(), w = Vec3::UnitZ(), point(0.03, 0.025, 0.01);
  const cut::CutReport report = cut::cut_mesh(
      box.mesh, cut::blade_sweep(point - u - w, point + u - w, point - u + w, point + u + w),
      kExact);
  // The labels by hand: the tet holding each face.
  std::vector<int> face_labels;
  for (Eigen::Index f = 0; f < report.crack_faces.rows(); ++f) {
    for (int t = 0; t < box.mesh.num_tets(); ++t) {
      int shared = 0;
      for (int k = 0; k < 4; ++k) {
        for (int c = 0; c < 3; ++c)
          shared += box.mesh.tets(t, k) == report.crack_faces(f, c) ? 1 : 0;
      }
      if (shared == 3) {
        face_labels.push_back(box.mesh.labels(t));
        break;
      }
    }
  }
  ASSERT_EQ(face_labels.size(), static_cast<std::size_t>(report.crack_faces.rows()));
  const CutDamage given = box.tracker.record_cut(box.mesh.rest, report.crack_faces, face_labels);
  EXPECT_TRUE(given.never_event);
  EXPECT_NEAR(given.protected_area, kLx * kLz, 1e-15);
  EXPECT_NEAR(given.area, kLx * kLz, 1e-15);
  try {
    box.tracker.record_cut(box.mesh.rest, report.crack_faces, std::vector<int>(1, 0));
    FAIL() << "wrong label count accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("labels has 1 entries"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace incise::sim::tools
