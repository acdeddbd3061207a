// Grasping an adaptive body (Paloc 2006's point): on a coarse mesh the vertex nearest to the
// forceps can lie far from them; refining the grasper's refine_request region first puts more
// vertices between the jaws, closer to the tips. Then the grasp is driven through hold() on the
// body's vertex slots, and the release's resimplify region decimates the body back.

#include <algorithm>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "grasp_fixtures.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"
#include "sim/remesh/adaptive_body.h"
#include "sim/remesh/size_field.h"
#include "sim/scene/scene_run.h"

namespace incise::sim::tools {
namespace {

// The body's surface vertices as vertex slots (the grasp candidates).
std::vector<int> surface_slots(const remesh::AdaptiveBody& body) {
  std::vector<int> slot_of;
  const TetMesh compact = body.to_tet_mesh(&slot_of);
  std::vector<int> slots;
  for (const int node : boundary_surface(compact).nodes) {
    slots.push_back(slot_of[static_cast<std::size_t>(node)]);
  }
  return slots;
}

Real nearest_to(const Points& x, const std::vector<int>& vertices, const Vec3& p) {
  Real best = std::numeric_limits<Real>::infinity();
  for (const int i : vertices)
    best = std::min(best, (row3(x, i) - p).norm());
  return best;
}

TEST(GraspRefine, RefiningBeforeTheGrabPutsMoreVerticesBetweenTheJaws) {
  const Scene scene = testing::scene_for(MaterialModel::mass_spring);
  const remesh::ModelFactory factory = [scene](const TetMesh& m) { return make_model(scene, m); };
  remesh::AdaptiveBody body(make_box_mesh(Vec3(0.04, 0.04, 0.02), Vec3i(4, 4, 2)), factory);
  body.set_fixed([](const Vec3& p) { return p.z() == 0; });

  GraspSettings settings;  // jaws 1 cm, radius 1 mm + margin 0.5 mm
  settings.reach = 0.008;
  // Forceps lying on the top face, closing on it: along +x from (1, 1.5) cm to (2, 1.5) cm, the
  // line midway between two rows of the 1 cm grid (5 mm from every vertex).
  JawPose pose;
  pose.pivot = Vec3(0.01, 0.015, 0.02);
  pose.direction = Vec3::UnitX();
  pose.opening_normal = Vec3::UnitZ();
  pose.opening_angle = 0.05;

  // Coarse: nothing within the jaws, so Paloc 2006's nearest vertex, 5 mm from the tips.
  Grasper coarse(settings);
  coarse.set_jaws(pose);
  const Vec3 tips = 0.5 * (coarse.jaws().jaws[0].b + coarse.jaws().jaws[1].b);
  const Vec3 middle = 0.5 * (pose.pivot + tips);
  std::vector<int> candidates = surface_slots(body);
  const std::optional<RestRegion> request =
      coarse.refine_request(body.slot_view().rest, body.x(), body.inverse_masses(), candidates);
  ASSERT_EQ(coarse.grab(body.slot_view().rest, body.x(), body.inverse_masses(), candidates), 1);
  const Real coarse_distance = nearest_to(body.x(), coarse.grabbed(), tips);
  EXPECT_NEAR(coarse_distance, 0.005, 1e-5);

  // The body is at rest, so the request is centred exactly under the middle of the jaws, and
  // holds the whole jaws.
  ASSERT_TRUE(request.has_value());
  EXPECT_LT((request->centre - middle).norm(), 1e-12);
  EXPECT_GT(request->radius, settings.jaw_length / 2 + settings.jaw_radius);

  // Refine there (2 mm target, 1.5 mm floor), then grab again with a fresh closing.
  remesh::RefinementSettings refinement;
  refinement.l_min = 0.0015;
  const int before = body.num_vertices();
  body.refine(remesh::sphere_size_field(request->centre, request->radius, 0.002), refinement);
  ASSERT_GT(body.num_vertices(), before);
  candidates = surface_slots(body);
  Grasper refined(settings);
  refined.set_jaws(pose);
  const int grabbed =
      refined.grab(body.slot_view().rest, body.x(), body.inverse_masses(), candidates);
  const Real refined_distance = nearest_to(body.x(), refined.grabbed(), tips);
  std::printf(
      "[ grasp ] coarse: 1 vertex at %.2f mm; refined (+%d vertices): %d within the jaws, "
      "nearest at %.2f mm\n",
      1e3 * coarse_distance, body.num_vertices() - before, grabbed, 1e3 * refined_distance);
  EXPECT_GT(grabbed, 3);
  EXPECT_LT(refined_distance, settings.jaw_radius + settings.grab_margin);
  for (const int i : refined.grabbed())
    EXPECT_GT(body.inverse_masses()[i], 0);

  // Drive the body's slots through hold(): lift the jaws 3 mm, the held slots follow.
  const std::vector<int> held = refined.grabbed();
  const Points at_grab = body.x();
  const Real dt = testing::stable_dt(body.to_tet_mesh()) * 0.5;
  constexpr int kSteps = 100;
  for (int k = 1; k <= kSteps; ++k) {
    JawPose lifted = pose;
    lifted.pivot.z() += 0.003 * k / kSteps;
    refined.set_jaws(lifted);
    body.step(dt, Vec3::Zero(), Points());
    refined.hold(dt, body.x(), body.v());
  }
  for (const int i : held) {
    EXPECT_NEAR(body.x()(i, 2) - at_grab(i, 2), 0.003, 1e-12);
  }

  // Open: the resimplify region holds every vertex refinement added near the jaws' patch, and
  // decimating outside nothing brings the body back to its original vertices.
  JawPose opened = pose;
  opened.opening_angle = 0.5;
  const std::optional<ReleaseEvent> event = refined.set_jaws(opened);
  ASSERT_TRUE(event.has_value());
  EXPECT_EQ(event->reason, ReleaseReason::opened);
  for (const int i : held) {
    EXPECT_LE((row3(body.slot_view().rest, i) - event->resimplify.centre).norm(),
              event->resimplify.radius);
  }
  const remesh::SizeField nowhere = [](const Vec3&) {
    return std::numeric_limits<Real>::infinity();
  };
  for (int round = 0; round < 50 && body.num_vertices() > before; ++round) {
    body.decimate(nowhere, 200);
  }
  EXPECT_EQ(body.num_vertices(), before);
}

}  // namespace
}  // namespace incise::sim::tools
