// Tests of sim/tools/blade_in_tissue.h on box meshes, whose depths are known in closed form: an
// upright blade in a block is in as deep as its tip (through a face, an edge or a vertex of the
// surface), an oblique one by the depth over the cosine; out above and below, wholly in when
// deeper than it is long (if the surface is within reach); through two bodies, two stretches (one
// if bridged); across or along a closed crack (two bodies touching), no gap; the same in a moved
// frame.

#include "sim/tools/blade_in_tissue.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "sim/collide/mesh_surface_faces.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"

namespace incise::sim::tools {
namespace {

const Vec3 kDown(0, 0, -1);

// Box meshes as one tissue (separate bodies, each box's nodes its own), with the surface tree.
struct Tissue {
  TetMesh mesh;
  Triangles faces;
  collide::SurfaceBvh bvh;

  explicit Tissue(const std::vector<std::pair<Vec3, Vec3>>& boxes) {  // (origin, size)
    Points rest(0, 3);
    Tets tets(0, 4);
    for (const auto& [origin, size] : boxes) {
      const Vec3i cells = (size / 0.01).array().round().cast<int>().max(1).matrix();
      const TetMesh box = make_box_mesh(size, cells);
      const auto n0 = rest.rows(), t0 = tets.rows();
      rest.conservativeResize(n0 + box.num_nodes(), 3);
      rest.bottomRows(box.num_nodes()) = box.rest.rowwise() + origin.transpose();
      tets.conservativeResize(t0 + box.num_tets(), 4);
      tets.bottomRows(box.num_tets()) = box.tets.array() + static_cast<int>(n0);
    }
    mesh = make_tet_mesh(rest, tets);
    faces = collide::mesh_surface_faces(boundary_surface(mesh));
    bvh.build(mesh.x, faces);
  }

  BladeInTissue blade(const Vec3& tip, const Vec3& direction, Real length, Real reach = 0.2,
                      Real bridge = 0) {
    BladeInTissue found;
    blade_in_tissue(bvh, mesh.x, tip, direction, length, reach, bridge, found);
    return found;
  }

  // The z of a face's nodes if they share one, else NaN.
  Real face_z(int slot) const {
    const Vec3i& t = bvh.triangle(slot);
    const Real z = mesh.x(t[0], 2);
    return mesh.x(t[1], 2) == z && mesh.x(t[2], 2) == z ? z
                                                        : std::numeric_limits<Real>::quiet_NaN();
  }
};

const std::pair<Vec3, Vec3> kBlock{Vec3::Zero(), Vec3(0.06, 0.06, 0.03)};

TEST(BladeInTissue, AnUprightBladeIsInAsDeepAsItsTip) {
  Tissue tissue({kBlock});
  // Inside a face, on a face's diagonal, on a grid edge, on a grid vertex (10 mm cells).
  for (const Vec3& xy : {Vec3(0.0137, 0.0242, 0), Vec3(0.025, 0.025, 0), Vec3(0.0137, 0.02, 0),
                         Vec3(0.03, 0.02, 0)}) {
    SCOPED_TRACE(xy.transpose());
    const BladeInTissue found = tissue.blade(xy + Vec3(0, 0, 0.023), kDown, 0.012);
    EXPECT_NEAR(found.depth, 0.007, 1e-12);
    ASSERT_EQ(found.stretches.size(), 1u);
    EXPECT_EQ(found.stretches[0].from, 0);
    EXPECT_NEAR(found.stretches[0].to, 0.007, 1e-12);
    EXPECT_EQ(tissue.face_z(found.stretches[0].face), 0.03);  // left through the top
  }
}

TEST(BladeInTissue, AnObliqueBladeIsInByTheDepthOverTheCosine) {
  Tissue tissue({kBlock});
  for (const Real degrees : {10.0, 30.0, 60.0}) {
    const Real angle = degrees * std::numbers::pi / 180;
    const Vec3 direction(std::sin(angle), 0, -std::cos(angle));
    const BladeInTissue found = tissue.blade(Vec3(0.0313, 0.0271, 0.025), direction, 0.02);
    EXPECT_NEAR(found.depth, 0.005 / std::cos(angle), 1e-12) << degrees << " degrees";
  }
}

TEST(BladeInTissue, ABladeAboveOrBelowTheTissueIsOut) {
  Tissue tissue({kBlock});
  const Vec3 xy(0.0137, 0.0242, 0);
  const BladeInTissue above = tissue.blade(xy + Vec3(0, 0, 0.035), kDown, 0.012);
  EXPECT_EQ(above.depth, 0);
  EXPECT_TRUE(above.stretches.empty());
  // Below, pointing up: the first face beyond the blade is the bottom, a way in.
  const BladeInTissue below = tissue.blade(xy + Vec3(0, 0, -0.03), -kDown, 0.012);
  EXPECT_EQ(below.depth, 0);
  // Beside the block, level with it.
  EXPECT_EQ(tissue.blade(Vec3(0.07, 0.03, 0.02), kDown, 0.012).depth, 0);
}

// Deeper than its length, the blade crosses no face: the top, found further up the shaft, is a
// way out, so the blade is wholly in; with the top out of reach, nothing tells, and it is out.
TEST(BladeInTissue, ABladeDeeperThanItsLengthIsWhollyInIfTheSurfaceIsWithinReach) {
  Tissue tissue({kBlock});
  const Vec3 tip(0.0137, 0.0242, 0.005);
  const BladeInTissue deep = tissue.blade(tip, kDown, 0.012);
  EXPECT_EQ(deep.depth, 0.012);
  ASSERT_EQ(deep.stretches.size(), 1u);
  EXPECT_EQ(tissue.face_z(deep.stretches[0].face), 0.03);
  EXPECT_EQ(tissue.blade(tip, kDown, 0.012, 0.005).depth, 0);
  EXPECT_EQ(tissue.blade(tip, kDown, 0.012, 0.014).depth, 0.012);
}

TEST(BladeInTissue, ABladeThroughTheBlockIsInForItsThickness) {
  Tissue tissue({kBlock});
  const BladeInTissue found = tissue.blade(Vec3(0.0137, 0.0242, -0.005), kDown, 0.05);
  EXPECT_NEAR(found.depth, 0.03, 1e-12);
  ASSERT_EQ(found.stretches.size(), 1u);
  EXPECT_NEAR(found.stretches[0].from, 0.005, 1e-12);
  EXPECT_NEAR(found.stretches[0].to, 0.035, 1e-12);
}

TEST(BladeInTissue, ThroughTwoBodiesItHasTwoStretches) {
  Tissue tissue(
      {{Vec3::Zero(), Vec3(0.04, 0.04, 0.01)}, {Vec3(0, 0, 0.015), Vec3(0.04, 0.04, 0.01)}});
  const BladeInTissue found = tissue.blade(Vec3(0.0137, 0.0242, 0.002), kDown, 0.03);
  EXPECT_NEAR(found.depth, 0.008 + 0.01, 1e-12);
  ASSERT_EQ(found.stretches.size(), 2u);
  EXPECT_NEAR(found.stretches[0].to, 0.008, 1e-12);
  EXPECT_NEAR(found.stretches[1].from, 0.013, 1e-12);
  EXPECT_NEAR(found.stretches[1].to, 0.023, 1e-12);
  EXPECT_EQ(tissue.face_z(found.stretches[0].face), 0.01);  // the lower body's top
  const Real z = tissue.face_z(found.stretches[1].face);    // the upper body's bottom or top
  EXPECT_TRUE(z == 0.015 || z == 0.025) << z;
  // Bridged, the 5 mm between them is no gap; a shorter bridge leaves it.
  const BladeInTissue bridged = tissue.blade(Vec3(0.0137, 0.0242, 0.002), kDown, 0.03, 0.2, 0.006);
  EXPECT_NEAR(bridged.depth, 0.023, 1e-12);
  ASSERT_EQ(bridged.stretches.size(), 1u);
  EXPECT_EQ(tissue.face_z(bridged.stretches[0].face), 0.01);
  EXPECT_NEAR(tissue.blade(Vec3(0.0137, 0.0242, 0.002), kDown, 0.03, 0.2, 0.004).depth, 0.018,
              1e-12);
}

// Two bodies touching are a closed crack: coincident faces with opposite normals. Across it the
// blade stays in (one stretch, taken ways out first at one place); lying in it (faces parallel
// to the blade) it is in as deep as its tip.
TEST(BladeInTissue, AClosedCrackIsNoGap) {
  Tissue stacked(
      {{Vec3::Zero(), Vec3(0.04, 0.04, 0.01)}, {Vec3(0, 0, 0.01), Vec3(0.04, 0.04, 0.01)}});
  const BladeInTissue across = stacked.blade(Vec3(0.0137, 0.0242, 0.004), kDown, 0.03);
  EXPECT_NEAR(across.depth, 0.016, 1e-12);
  ASSERT_EQ(across.stretches.size(), 1u);
  EXPECT_EQ(across.stretches[0].from, 0);
  Tissue side_by_side(
      {{Vec3::Zero(), Vec3(0.03, 0.04, 0.02)}, {Vec3(0.03, 0, 0), Vec3(0.03, 0.04, 0.02)}});
  for (const Real y : {0.0137, 0.02}) {
    const BladeInTissue along = side_by_side.blade(Vec3(0.03, y, 0.013), kDown, 0.012);
    EXPECT_NEAR(along.depth, 0.007, 1e-12) << "y = " << y;
  }
}

// Only the positions the tree was refit to count: the block turned and moved, with the blade.
TEST(BladeInTissue, TheSameInAMovedFrame) {
  Tissue tissue({kBlock});
  const Mat3 r = Eigen::AngleAxis<Real>(0.9, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  const Vec3 t(0.1, -0.05, 0.2);
  tissue.mesh.x = (tissue.mesh.rest * r.transpose()).rowwise() + t.transpose();
  tissue.bvh.refit(tissue.mesh.x);
  const Vec3 tip = r * Vec3(0.0137, 0.0242, 0.019) + t;
  EXPECT_NEAR(tissue.blade(tip, r * kDown, 0.02).depth, 0.011, 1e-12);
  EXPECT_NEAR(tissue.blade(tip, r * kDown, 0.008).depth, 0.008, 1e-12);
  EXPECT_EQ(tissue.blade(tip + r * Vec3(0, 0, 0.02), r * kDown, 0.008).depth, 0);
}

TEST(BladeInTissue, BadInputsAreRefused) {
  Tissue tissue({kBlock});
  BladeInTissue found;
  const Vec3 tip(0.01, 0.01, 0.02);
  const Real inf = std::numeric_limits<Real>::infinity();
  EXPECT_THROW(
      blade_in_tissue(tissue.bvh, tissue.mesh.x, Vec3(inf, 0, 0), kDown, 0.01, 0, 0, found),
      std::invalid_argument);
  EXPECT_THROW(blade_in_tissue(tissue.bvh, tissue.mesh.x, tip, 2 * kDown, 0.01, 0, 0, found),
               std::invalid_argument);
  EXPECT_THROW(blade_in_tissue(tissue.bvh, tissue.mesh.x, tip, kDown, 0, 0, 0, found),
               std::invalid_argument);
  EXPECT_THROW(blade_in_tissue(tissue.bvh, tissue.mesh.x, tip, kDown, 0.01, -1, 0, found),
               std::invalid_argument);
  EXPECT_THROW(blade_in_tissue(tissue.bvh, tissue.mesh.x, tip, kDown, 0.01, 0, -1e-3, found),
               std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::tools
