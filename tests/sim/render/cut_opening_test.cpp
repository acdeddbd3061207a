// The picture's opening of a cut (sim/render/cut_opening.h) on the closed form of a slit: a
// vertical crack of depth h in the top of a block, its two walls at x = 0 meeting along the floor
// z = -h. The rim vertices move apart by the gape, the floor's shared vertices stay, and nothing
// that is not on a wall moves.
#include "sim/render/cut_opening.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace incise::render {
namespace {

TEST(CutOpening, TheRimOpensByTheGapeAndTheFloorStaysClosed) {
  // Vertices: 0, 1 the rim of the left wall (x = 0, y = 0 and 1, z = 0); 2, 3 the rim of the right
  // wall (the same places: the crack's duplicates); 4, 5 the floor (y = 0 and 1, z = -1), shared;
  // 6, 7 the capsule beside the left rim (x = -1); 8 a capsule vertex beside the right rim.
  SurfacePositions V(9, 3);
  V << 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, -1, 0, 1, -1, -1, 0, 0, -1, 1, 0, 1, 0, 0;
  // The left wall faces +x (into the crack), the right wall -x; a capsule face on each side.
  SurfaceFaces F(6, 3);
  F << 0, 4, 5,  //  left wall: (4 - 0) x (5 - 0) = (0,0,-1) x (0,1,-1) = (1, 0, 0)
      0, 5, 1,   //  (0,1,-1) x (0,1,0) = (1, 0, 0)
      2, 5, 4,   //  right wall: (0,1,-1) x (0,0,-1) = (-1, 0, 0)
      2, 3, 5,   //  (0,1,0) x (0,1,-1) = (-1, 0, 0)
      6, 0, 1,   //  capsule (faces up)
      8, 3, 2;
  const std::vector<std::uint8_t> walls = {1, 1, 1, 1, 0, 0};
  const SurfacePositions before = V;
  std::vector<double> scratch;
  open_cut_walls(F, walls, 0.002, V, scratch);

  // Rim: each side's vertices move 1 mm into their own side, so the rim opens by 2 mm.
  for (const int left : {0, 1})
    EXPECT_NEAR(V(left, 0), -0.001, 1e-15) << left;
  for (const int right : {2, 3})
    EXPECT_NEAR(V(right, 0), 0.001, 1e-15) << right;
  // Floor: the two walls' normals cancel.
  for (const int floor : {4, 5})
    EXPECT_LT((V.row(floor) - before.row(floor)).norm(), 1e-15) << floor;
  // Off the walls: untouched, and only x moved anywhere.
  for (const int capsule : {6, 7, 8})
    EXPECT_EQ(V.row(capsule), before.row(capsule)) << capsule;
  EXPECT_EQ(V.col(1), before.col(1));
  EXPECT_EQ(V.col(2), before.col(2));

  // No walls, or flags that do not fit the faces: nothing moves.
  SurfacePositions again = before;
  open_cut_walls(F, std::vector<std::uint8_t>(6, 0), 0.002, again, scratch);
  EXPECT_EQ(again, before);
  open_cut_walls(F, {1, 1}, 0.002, again, scratch);
  EXPECT_EQ(again, before);
}

}  // namespace
}  // namespace incise::render
