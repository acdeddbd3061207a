// Cuts of box meshes (sim/cut/cut_mesh.h): through the whole body, against the closed-form volumes
// of the two parts of a box cut by a plane; partial, non-planar, repeated and crossing cuts on a
// regular and a jittered box in a deformed configuration, against every invariant of
// expect_cut_invariants; and a model that follows the cut through Model::update_elements.
// With INCISE_CUT_STRESS set, the random tests run 480 partial and 200 through cuts (about 3 s).

#include <array>
#include <cmath>
#include <cstdlib>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "cut_checks.h"
#include "sim/cut/cut_mesh.h"
#include "sim/mesh/box_mesher.h"
#include "sim/models/corotational_fem.h"

namespace incise::sim::cut {
namespace {

using testing::expect_cut_invariants;
using testing::jittered_box;
using testing::plane_blade;
using testing::tet_components;

constexpr Real kSnap = CutOptions{}.snap;

TetMesh unit_box(bool jitter) {
  TetMesh mesh =
      jitter ? jittered_box({1, 1, 1}, {4, 4, 4}, 0.2, 7) : make_box_mesh({1, 1, 1}, {4, 4, 4});
  for (int t = 0; t < mesh.num_tets(); ++t)
    mesh.labels(t) = t % 3;
  return mesh;
}

// A smooth deformation of the rest state (a bend and a stretch), and a rigid spin as velocity.
void deform(TetMesh& mesh) {
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Vec3 p = row3(mesh.rest, i);
    mesh.x.row(i) =
        (p + Vec3(0.05 * std::sin(2 * p.z()), 0.04 * p.x() * p.y(), 0.1 * p.z())).transpose();
    mesh.v.row(i) = Vec3(0.3, -0.2, 0.5).cross(p).transpose();
  }
}

// Volume [m^3] of each component, with the component of each tet.
std::vector<Real> component_volumes(const TetMesh& mesh, std::vector<int>& component) {
  int count = 0;
  component = tet_components(mesh.tets, &count);
  std::vector<Real> volume(static_cast<std::size_t>(count), 0);
  const VecX volumes = tet_volumes(mesh.rest, mesh.tets);
  for (int t = 0; t < mesh.num_tets(); ++t)
    volume[static_cast<std::size_t>(component[static_cast<std::size_t>(t)])] += volumes(t);
  return volume;
}

// No node belongs to tets of two components: the parts are separate.
void expect_no_shared_nodes(const TetMesh& mesh, const std::vector<int>& component) {
  std::vector<int> owner(static_cast<std::size_t>(mesh.num_nodes()), -1);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      int& o = owner[static_cast<std::size_t>(mesh.tets(t, k))];
      const int c = component[static_cast<std::size_t>(t)];
      EXPECT_TRUE(o < 0 || o == c) << "node " << mesh.tets(t, k) << " is shared across the crack";
      o = c;
    }
  }
}

// Cuts the unit box along the plane n . p = c (n with n.x > 0 and the plane crossing every line
// parallel to x inside the box) and checks the two parts against the closed form: the part
// n . p < c has volume int int (c - n.y y - n.z z) / n.x dy dz = (c - n.y / 2 - n.z / 2) / n.x.
void expect_plane_halves(bool jitter, const Vec3& n, Real c, Real snap, int expected_snapped) {
  const TetMesh before = unit_box(jitter);
  TetMesh mesh = before;
  const CutSurface blade = plane_blade(n * c / n.squaredNorm(), n, 3);
  const CutReport report = cut_mesh(mesh, blade, CutOptions{snap});
  EXPECT_EQ(report.snapped_nodes, expected_snapped);
  expect_cut_invariants(before, mesh, report, blade, snap);
  std::vector<int> component;
  const std::vector<Real> volume = component_volumes(mesh, component);
  ASSERT_EQ(volume.size(), 2u);
  expect_no_shared_nodes(mesh, component);
  // The component of node 0 (the origin, on the side n . p < c) comes first.
  int origin_side = -1;
  for (int t = 0; t < mesh.num_tets() && origin_side < 0; ++t) {
    for (int k = 0; k < 4; ++k) {
      if (mesh.tets(t, k) == 0) origin_side = component[static_cast<std::size_t>(t)];
    }
  }
  const Real below = (c - n.y() / 2 - n.z() / 2) / n.x();
  EXPECT_NEAR(volume[static_cast<std::size_t>(origin_side)], below, 1e-12);
  EXPECT_NEAR(volume[static_cast<std::size_t>(1 - origin_side)], 1 - below, 1e-12);
}

// Grid nodes have n . p in steps of 0.025 and edges change it by at most 0.375: c = 0.5375 keeps
// every crossing at t >= 0.0125 / 0.375 = 0.033 from an end, beyond a snap of 0.01, so the crack
// lies exactly on the plane (with the default 0.05, 3 nodes snap and the halves move by 2e-4).
TEST(CutMesh, ObliquePlaneThroughTheBoxGivesTheClosedFormHalves) {
  expect_plane_halves(false, {1, 0.3, 0.2}, 0.5375, 0.01, 0);
}

TEST(CutMesh, ObliquePlaneThroughAJitteredBoxGivesTheClosedFormHalves) {
  expect_plane_halves(true, {1, 0.3, 0.2}, 0.5375, 0.01, 0);
}

TEST(CutMesh, GridPlaneThroughNodesOpensFacesWithoutSubdivision) {
  // x = 1/2 holds 25 grid nodes and no edge crosses it: the faces there open, nothing is split.
  expect_plane_halves(false, {1, 0, 0}, 0.5, kSnap, 25);
  TetMesh mesh = unit_box(false);
  const CutReport report = cut_mesh(mesh, plane_blade({0.5, 0, 0}, {1, 0, 0}, 3));
  EXPECT_EQ(mesh.num_tets(), 320);
  EXPECT_EQ(mesh.num_nodes(), 125 + 25);
  EXPECT_EQ(report.faces_opened, 32);  // 16 cell faces of two triangles
}

TEST(CutMesh, DiagonalPlaneThroughNodesAndEdgesGivesTheClosedFormHalves) {
  // x + y = 1 passes through grid nodes and along face diagonals: the vertex and edge cases.
  expect_plane_halves(false, {1, 1, 0}, 1, kSnap, 25);
}

TEST(CutMesh, CrossingThroughCutsGiveFourParts) {
  const TetMesh box = unit_box(true);
  TetMesh mesh = box;
  const Vec3 n1(1, 0.3, 0.2);
  const Vec3 n2(0.2, 1, -0.1);
  const CutSurface first = plane_blade(n1 * 0.537 / n1.squaredNorm(), n1, 3);
  const CutReport r1 = cut_mesh(mesh, first);
  expect_cut_invariants(box, mesh, r1, first, kSnap);
  const TetMesh once = mesh;
  const CutSurface second = plane_blade(n2 * 0.55 / n2.squaredNorm(), n2, 3);
  const CutReport r2 = cut_mesh(mesh, second);
  expect_cut_invariants(once, mesh, r2, second, kSnap);
  std::vector<int> component;
  const std::vector<Real> volume = component_volumes(mesh, component);
  ASSERT_EQ(volume.size(), 4u);
  expect_no_shared_nodes(mesh, component);
  // The parts below the first plane add up to its closed-form half (the second cut may move
  // nodes near the first crack by snapping, but only along the second plane).
  // A part is below the first plane if its centre of volume is.
  std::vector<Real> moment(volume.size(), 0);  // of n1 . p
  const VecX volumes = tet_volumes(mesh.rest, mesh.tets);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Vec3 centroid = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
      centroid += row3(mesh.rest, mesh.tets(t, k)) / 4;
    moment[static_cast<std::size_t>(component[static_cast<std::size_t>(t)])] +=
        volumes(t) * n1.dot(centroid);
  }
  Real below_volume = 0;
  for (std::size_t c = 0; c < volume.size(); ++c)
    below_volume += (moment[c] / volume[c] < 0.537) ? volume[c] : 0;
  // Snapping moves the crack by at most snap times the longest edge (< 0.5 m here) over a cross
  // section of less than 1.2 m^2.
  EXPECT_NEAR(below_volume, 0.537 - 0.15 - 0.1, kSnap * 0.5 * 1.2);
}

// Random blades smaller than the body: the crack stops inside, where its front stays closed.
void random_partial_cuts(bool jitter, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<Real> unit(0, 1);
  std::normal_distribution<Real> normal(0, 1);
  TetMesh mesh = unit_box(jitter);
  deform(mesh);
  for (int cut = 0; cut < 4; ++cut) {
    const TetMesh before = mesh;
    const Vec3 point(0.2 + 0.6 * unit(random), 0.2 + 0.6 * unit(random), 0.2 + 0.6 * unit(random));
    const Vec3 n(normal(random), normal(random), normal(random));
    const CutSurface blade = plane_blade(point, n, 0.2 + 0.3 * unit(random));
    const CutReport report = cut_mesh(mesh, blade);
    SCOPED_TRACE("seed " + std::to_string(seed) + " cut " + std::to_string(cut));
    expect_cut_invariants(before, mesh, report, blade, kSnap);
    // New nodes on an edge carry the edge's t in rest, current positions and velocities alike.
    for (std::size_t k = 0; k < report.new_nodes.size(); ++k) {
      const NodeOrigin& o = report.new_nodes[k];
      const int i = report.first_new_node + static_cast<int>(k);
      const Real s = (o.b < 0) ? 0 : o.t;
      const int b = (o.b < 0) ? o.a : o.b;
      for (const Points* p : {&mesh.rest, &mesh.x, &mesh.v}) {
        const Vec3 expected = (1 - s) * row3(*p, o.a) + s * row3(*p, b);
        EXPECT_LE((row3(*p, i) - expected).norm(), 1e-15);
      }
    }
  }
}

TEST(CutMesh, RandomPartialPlanarCutsKeepTheInvariants) {
  for (unsigned seed = 1; seed <= (std::getenv("INCISE_CUT_STRESS") ? 60u : 3u); ++seed) {
    random_partial_cuts(false, seed);
    random_partial_cuts(true, seed);
  }
}

TEST(CutMesh, RandomThroughCutsSeparateTheBoxInTwo) {
  std::mt19937 random(11);
  std::uniform_real_distribution<Real> unit(0, 1);
  std::normal_distribution<Real> normal(0, 1);
  const int cuts = std::getenv("INCISE_CUT_STRESS") ? 200 : 6;
  for (int cut = 0; cut < cuts; ++cut) {
    const bool jitter = cut % 2 == 1;
    TetMesh mesh = unit_box(jitter);
    deform(mesh);
    const TetMesh before = mesh;
    const Vec3 point(0.3 + 0.4 * unit(random), 0.3 + 0.4 * unit(random), 0.3 + 0.4 * unit(random));
    const Vec3 n(normal(random), normal(random), normal(random));
    const CutSurface blade = plane_blade(point, n, 3);
    const CutReport report = cut_mesh(mesh, blade);
    SCOPED_TRACE("cut " + std::to_string(cut));
    std::vector<int> component;
    EXPECT_EQ(component_volumes(mesh, component).size(), 2u);
    expect_no_shared_nodes(mesh, component);
  }
}

TEST(CutMesh, NonPlanarBladePathKeepsTheInvariants) {
  // The blade turns and twists along an arc through the (deformed) jittered box.
  const int poses = 9;
  Points a(poses, 3);
  Points b(poses, 3);
  for (int k = 0; k < poses; ++k) {
    const Real s = static_cast<Real>(k) / (poses - 1);
    const Real angle = 1.2 * s;
    const Vec3 centre(-0.2 + 1.4 * s, 0.5 + 0.2 * std::sin(3 * s), 0.5);
    const Vec3 along(0.3 * std::sin(angle), 0.3 * std::sin(angle), std::cos(angle));
    a.row(k) = (centre - 0.4 * along.normalized()).transpose();
    b.row(k) = (centre + 0.4 * along.normalized()).transpose();
  }
  const CutSurface blade = blade_path(a, b);
  for (bool jitter : {false, true}) {
    TetMesh mesh = unit_box(jitter);
    deform(mesh);
    const TetMesh before = mesh;
    const CutReport report = cut_mesh(mesh, blade);
    expect_cut_invariants(before, mesh, report, blade, kSnap);
    EXPECT_GT(report.crack_faces.rows(), 0);
  }
}

TEST(CutMesh, ModelFollowsTheCutAndStaysForceFreeAtRest) {
  TetMesh mesh = unit_box(true);
  const std::vector<ElementMaterial> materials(3, ElementMaterial{1e4, 0.3, 1000, 0});
  CorotationalFem model(mesh, materials, RotationExtraction::polar);
  const Real mass = model.masses().sum();
  const CutReport report = cut_mesh(mesh, plane_blade({0.5, 0.5, 0.5}, {1, 0.4, 0.1}, 0.3));
  ASSERT_FALSE(report.changed_tets.empty());
  const std::vector<char> alive(static_cast<std::size_t>(mesh.num_tets()), 1);
  model.update_elements(mesh, alive, report.changed_tets);
  ASSERT_EQ(model.masses().size(), mesh.num_nodes());
  EXPECT_NEAR(model.masses().sum(), mass, 1e-9 * mass);
  Points f = Points::Zero(mesh.num_nodes(), 3);
  model.add_forces(mesh.rest, Points::Zero(mesh.num_nodes(), 3), f);
  EXPECT_LE(f.cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(model.health().inverted_elements, 0);
}

}  // namespace
}  // namespace incise::sim::cut
