// Bad input to the damage metrics gets std::invalid_argument with a precise message, and a
// rejected call leaves the tracker as it was.

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/mesh/box_mesher.h"
#include "sim/tools/damage_tracker.h"

namespace incise::sim::tools {
namespace {

constexpr Real kNan = std::numeric_limits<Real>::quiet_NaN();

template <typename Call>
void expect_invalid(Call&& call, const std::string& message) {
  try {
    call();
    ADD_FAILURE() << "no exception, expected: " << message;
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TetMesh cube() {
  return make_box_mesh(Vec3(1, 1, 1), Vec3i(1, 1, 1));
}

DamageSettings threshold(Real value, int label = 0) {
  DamageSettings settings;
  settings.strain_thresholds = {{label, value}};
  return settings;
}

TEST(DamageInput, BadSettings) {
  const TetMesh mesh = cube();
  expect_invalid([&] { DamageTracker(mesh, threshold(0)); },
                 "DamageTracker: the strain threshold of label 0 must be finite and > 0, got "
                 "0.000000");
  expect_invalid([&] { DamageTracker(mesh, threshold(-0.1, 4)); },
                 "DamageTracker: the strain threshold of label 4 must be finite and > 0, got "
                 "-0.100000");
  expect_invalid([&] { DamageTracker(mesh, threshold(kNan)); },
                 "DamageTracker: the strain threshold of label 0 must be finite and > 0, got nan");
  DamageSettings twice = threshold(0.1, 2);
  twice.strain_thresholds.push_back({2, 0.3});
  expect_invalid([&] { DamageTracker(mesh, twice); },
                 "DamageTracker: label 2 has two strain thresholds");
  DamageSettings structures;
  structures.protected_structures = -1;
  expect_invalid([&] { DamageTracker(mesh, structures); },
                 "DamageTracker: protected_structures must be >= 0, got -1");
}

TEST(DamageInput, BadTarget) {
  MarkedTarget target;
  target.line.resize(1, 3);
  target.line << 0, 0, 0;
  target.depth = 0.01;
  target.half_width = 0.001;
  expect_invalid([&] { validate_target(target); },
                 "MarkedTarget: the marked line needs at least 2 points, got 1");
  target.line.resize(2, 3);
  target.line << 0, 0, 0, 0, 0, 0;
  expect_invalid([&] { validate_target(target); },
                 "MarkedTarget: segment 0 of the marked line has zero length");
  target.line << 0, 0, 0, 1, 0, kNan;
  expect_invalid([&] { validate_target(target); },
                 "MarkedTarget: the marked line holds a non-finite coordinate");
  target.line << 0, 0, 0, 1, 0, 0;
  target.depth_direction = Vec3::Zero();
  expect_invalid([&] { validate_target(target); },
                 "MarkedTarget: depth_direction must be finite and non-zero");
  target.depth_direction = -Vec3::UnitZ();
  target.half_width = 0;
  expect_invalid([&] { validate_target(target); },
                 "MarkedTarget: half_width must be finite and > 0, got 0.000000 m");
  target.half_width = 0.001;
  target.depth = kNan;
  DamageSettings settings;
  settings.target = target;
  expect_invalid([&] { DamageTracker(cube(), settings); },
                 "MarkedTarget: depth must be finite and > 0, got nan m");
}

TEST(DamageInput, BadMesh) {
  TetMesh mesh = cube();
  expect_invalid([&] { DamageTracker(mesh, std::vector<char>(3, 1), threshold(0.1)); },
                 "DamageTracker: alive has 3 entries for 5 tet slots");
  std::swap(mesh.tets(2, 0), mesh.tets(2, 1));
  expect_invalid([&] { DamageTracker(mesh, threshold(0.1)); },
                 "DamageTracker: tet slot 2 has rest volume -0.166667 m^3 (flat or inverted at "
                 "rest)");
  std::vector<char> alive(5, 1);
  alive[2] = 0;  // a dead slot may hold anything
  EXPECT_NO_THROW(DamageTracker(mesh, alive, threshold(0.1)));
  mesh.tets(2, 0) = 9;
  alive[2] = 1;
  expect_invalid([&] { DamageTracker(mesh, alive, threshold(0.1)); },
                 "DamageTracker: tet slot 2 holds node 9, outside [0, 8)");
}

TEST(DamageInput, BadStepsLeaveTheStateAsItWas) {
  const TetMesh mesh = cube();
  DamageTracker tracker(mesh, threshold(0.01));
  Points x = mesh.rest;
  x.col(0) *= 1.1;
  tracker.record_strain(x, 0.001);
  const DamageMetrics before = tracker.metrics();

  expect_invalid([&] { tracker.record_strain(x, 0); },
                 "DamageTracker::record_strain: dt must be finite and > 0, got 0.000000 s");
  expect_invalid([&] { tracker.record_strain(x, kNan); },
                 "DamageTracker::record_strain: dt must be finite and > 0, got nan s");
  expect_invalid([&] { tracker.record_strain(x.topRows(7), 0.001); },
                 "DamageTracker::record_strain: x has 7 rows, the tets use 8 nodes");
  Points bad = x;
  bad(7, 2) = kNan;
  const int first_bad = [&] {
    for (int s = 0; s < mesh.num_tets(); ++s) {
      if ((mesh.tets.row(s).array() == 7).any()) return s;
    }
    return -1;
  }();
  expect_invalid([&] { tracker.record_strain(bad, 0.001); },
                 "DamageTracker::record_strain: the strain of tet slot " +
                     std::to_string(first_bad) + " is not finite (x holds NaN or infinity)");
  EXPECT_EQ(tracker.metrics().max_time_over_threshold, before.max_time_over_threshold);
  EXPECT_EQ(tracker.time_over_threshold(), VecX::Constant(5, 0.001));

  expect_invalid([&] { tracker.record_contacts(std::vector<Real>{0.1}, 0.001); },
                 "DamageTracker::record_contacts: got 1 depths for 0 protected structures");
}

TEST(DamageInput, BadContactsAndUpdates) {
  const TetMesh mesh = cube();
  DamageSettings settings;
  settings.protected_structures = 1;
  DamageTracker tracker(mesh, settings);
  expect_invalid([&] { tracker.record_contacts(std::vector<Real>{kNan}, 0.001); },
                 "DamageTracker::record_contacts: the depth of protected structure 0 is not "
                 "finite");
  expect_invalid([&] { tracker.record_contacts(std::vector<Real>{0.1}, -1); },
                 "DamageTracker::record_contacts: dt must be finite and > 0, got -1.000000 s");
  EXPECT_EQ(tracker.metrics().protected_collisions, 0);

  const std::vector<char> alive(5, 1);
  const std::vector<int> changed = {1, 7};
  const std::vector<int> one = {0};
  expect_invalid([&] { tracker.update_elements(mesh, alive, changed, one); },
                 "DamageTracker::update_elements: parents has 1 entries for 2 changed slots");
  const std::vector<int> parents = {0, 0};
  expect_invalid([&] { tracker.update_elements(mesh, alive, changed, parents); },
                 "DamageTracker::update_elements: changed slot 7 is outside [0, 5)");
  const std::vector<int> slot = {1};
  const std::vector<int> far = {5};
  expect_invalid([&] { tracker.update_elements(mesh, alive, slot, far); },
                 "DamageTracker::update_elements: parent 5 of slot 1 is outside [-1, 5)");
  TetMesh flat = mesh;
  flat.rest.row(flat.tets(1, 3)) = flat.rest.row(flat.tets(1, 0));
  const std::vector<int> same = {1};
  expect_invalid([&] { tracker.update_elements(flat, alive, slot, same); },
                 "DamageTracker: tet slot 1 has rest volume 0.000000 m^3 (flat or inverted at "
                 "rest)");
  EXPECT_EQ(tracker.metrics().tracked_volume, 0);  // no threshold: nothing tracked, unchanged

  Triangles face(1, 3);
  face << 0, 1, 9;
  expect_invalid([&] { tracker.record_cut(mesh.rest, face); },
                 "DamageTracker::record_cut: crack face 0 holds node 9, outside [0, 8)");
  face << 0, 1, 7;  // opposite corners of the cube: no tet of the 5-tet split holds both
  expect_invalid([&] { tracker.record_cut(mesh.rest, face); },
                 "DamageTracker::record_cut: no alive tet holds crack face 0 (0, 1, 7): call "
                 "update_elements first");
}

}  // namespace
}  // namespace incise::sim::tools
