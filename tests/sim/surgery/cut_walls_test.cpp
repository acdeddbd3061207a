// Which boundary faces are cut walls (sim/surgery/cut_walls.h), on a box mesh whose sides are the
// closed form: refinement leaves every face on the box's sides, so none is a wall; removing a
// block of tets (a notch, the shape of an opened cut) exposes faces inside the box, exactly the
// walls.
#include "sim/surgery/cut_walls.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sim/collide/mesh_surface_faces.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"
#include "sim/surgery/bisection.h"

namespace incise::sim::surgery {
namespace {

const Vec3 kSize(0.06, 0.06, 0.03);

bool on_a_side(const Vec3& p) {
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(p(axis)) < 1e-12 || std::abs(p(axis) - kSize(axis)) < 1e-12) return true;
  }
  return false;
}

Vec3 rest_centroid(const TetMesh& mesh, const BoundarySurface& surface, int f) {
  Vec3 c = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
    c += row3(mesh.rest, surface.nodes[static_cast<std::size_t>(surface.faces(f, k))]);
  return c / 3;
}

TEST(CutWalls, RefinedCapsuleHasNoWallsAndANotchsFacesInsideTheBoxAreExactlyTheWalls) {
  TetMesh mesh = make_box_mesh(kSize, Vec3i(6, 6, 3));
  CutWalls walls(mesh.rest, collide::mesh_surface_faces(boundary_surface(mesh)));
  std::vector<std::uint8_t> flags;
  BoundarySurface surface = boundary_surface(mesh);
  walls.classify(mesh.rest, surface, flags);
  ASSERT_EQ(flags.size(), static_cast<std::size_t>(surface.faces.rows()));
  for (const std::uint8_t f : flags)
    EXPECT_EQ(f, 0);

  // Refined at a corner of the top: more faces, all still on the sides.
  BisectionSettings settings;
  settings.edge_length = 0.004;
  ASSERT_GT(refine_ball(mesh, Vec3(0.03, 0.03, 0.03), 0.012, settings).splits, 20);
  surface = boundary_surface(mesh);
  walls.classify(mesh.rest, surface, flags);
  ASSERT_EQ(flags.size(), static_cast<std::size_t>(surface.faces.rows()));
  for (const std::uint8_t f : flags)
    EXPECT_EQ(f, 0);

  // A notch: the tets whose centroid lies in x < 3 cm and z > 1.5 cm are removed.
  std::vector<int> kept;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
      c += row3(mesh.rest, mesh.tets(t, k)) / 4;
    if (!(c.x() < 0.03 && c.z() > 0.015)) kept.push_back(t);
  }
  ASSERT_LT(kept.size(), static_cast<std::size_t>(mesh.num_tets()));
  TetMesh notched = mesh;
  notched.tets.resize(static_cast<Eigen::Index>(kept.size()), 4);
  notched.labels.resize(static_cast<Eigen::Index>(kept.size()));
  for (std::size_t i = 0; i < kept.size(); ++i) {
    notched.tets.row(static_cast<Eigen::Index>(i)) = mesh.tets.row(kept[i]);
    notched.labels(static_cast<Eigen::Index>(i)) = mesh.labels(kept[i]);
  }
  surface = boundary_surface(notched);
  walls.classify(notched.rest, surface, flags);
  int wall_faces = 0;
  for (int f = 0; f < surface.faces.rows(); ++f) {
    const bool wall = !on_a_side(rest_centroid(notched, surface, f));
    EXPECT_EQ(flags[static_cast<std::size_t>(f)], wall ? 1 : 0) << "face " << f;
    wall_faces += wall;
  }
  EXPECT_GT(wall_faces, 10);

  // Asked again, the answers come from the cache and are the same.
  const std::vector<std::uint8_t> first = flags;
  walls.classify(notched.rest, surface, flags);
  EXPECT_EQ(flags, first);
}

}  // namespace
}  // namespace incise::sim::surgery
